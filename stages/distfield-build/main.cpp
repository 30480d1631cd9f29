// ausbau-distfield-build: the FARR distance fields of a scene (thesis 4.2.2),
// one for S (all static meshes merged, world coordinates) and one for D (in
// the planning convention: D's mesh relative to its reference point), as
// ausbau-distfield artifacts. See README.md beside this file.
#include <cstdio>
#include <filesystem>

#include "artifact/artifact.h"
#include "artifact/run_files.h"
#include "cli/stage.h"
#include "collision/distance_field.h"
#include "core/log.h"
#include "planning/state_space.h"
#include "scene/scene.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

struct DistfieldBuildOptions {
  std::string output_dir;  // -o DIR: DIR/distfield-static.h5, DIR/distfield-dynamic.h5
  std::string static_out;  // or both files explicitly
  std::string dynamic_out;
  double memory_budget_gib = 4.0;
  DistanceFieldOptions field;
};

// No artifact of the runner's: the two fields are cached by the distance
// field cache (DefaultDistanceFieldCacheDir), whose entries carry their own
// provenance; --force builds them again.
constexpr StageSpec kDistfieldBuildStage{
    "ausbau-distfield-build",
    "Builds the FARR distance fields of S and D (thesis 4.2.2) for ausbau-plan --collision farr.",
    SceneHash::kWholeScene,
    {},
    {},
    "build even when the output is up to date"};

// The memory limit in bytes and the field's own check.
DistanceFieldOptions FieldOptions(const DistfieldBuildOptions& options) {
  if (!(options.memory_budget_gib > 0)) throw InputError("--memory-limit: must be > 0 GiB");
  DistanceFieldOptions field = options.field;
  field.memory_budget_bytes = static_cast<std::uint64_t>(options.memory_budget_gib * double(1 << 30));
  field.Check();
  return field;
}

void DeclareDistfieldBuild(StageDefinition& stage, DistfieldBuildOptions* options) {
  stage
      .Option("--field-cells", &options->field.resolution, "cells along the longest axis of 1.3x the AABB",
              CacheKey::kYes)
      ->check(Within(2, kMaxDistanceFieldResolution));
  stage.Threads(&options->field.threads);
  stage.Option("--memory-limit", &options->memory_budget_gib, "GiB; larger fields are refused", CacheKey::kNo);
  stage.OutputFolder("--output-dir", &options->output_dir,
                     "write DIR/distfield-static.h5 and DIR/distfield-dynamic.h5 (default: the cache)");
  stage.ExtraOutput("--static-out", &options->static_out, "the field of S (with --dynamic-out)");
  stage.ExtraOutput("--dynamic-out", &options->dynamic_out, "the field of D (with --static-out)");
  AddRenamedFlag(stage.app(), "--resolution", "--field-cells");
  AddRenamedFlag(stage.app(), "--memory-budget", "--memory-limit");
  stage.CheckOptions([options] {
    FieldOptions(*options);
    if (!options->output_dir.empty() && (!options->static_out.empty() || !options->dynamic_out.empty())) {
      throw InputError("--output-dir: give either --output-dir DIR or --static-out and --dynamic-out, not both");
    }
    if (options->static_out.empty() != options->dynamic_out.empty()) {
      throw InputError("--static-out and --dynamic-out: give both or neither");
    }
  });
}

int BuildDistanceFields(const StageRun& run, const DistfieldBuildOptions& options) {
  DistanceFieldOptions field = FieldOptions(options);
  field.progress = ShowProgress("distance field");
  fs::path static_target = options.static_out, dynamic_target = options.dynamic_out;
  if (!options.output_dir.empty()) {
    static_target = fs::path(options.output_dir) / kRunFileDistfieldStatic;
    dynamic_target = fs::path(options.output_dir) / kRunFileDistfieldDynamic;
  }
  const Scene& scene = run.scene;
  const PlanningProblem problem = MakePlanningProblem(scene);
  const fs::path cache_dir = DefaultDistanceFieldCacheDir(scene.file);
  LogInfo("scene %s: S %zu triangles, D %zu triangles, resolution %d, cache %s", scene.name.c_str(),
          problem.environment.triangles.size(), problem.robot.triangles.size(), field.resolution,
          cache_dir.empty() ? "none" : cache_dir.string().c_str());
  const fs::path s = MakeDistanceFieldFile(problem.environment, field, cache_dir, static_target, run.force,
                                           "distance field of S", scene.units, "world");
  const fs::path d = MakeDistanceFieldFile(problem.robot, field, cache_dir, dynamic_target, run.force,
                                           "distance field of D", scene.units, "D relative to its reference point");
  // Machine-readable: the two files, as --distfield of ausbau-plan takes them.
  std::printf("%s,%s\n", s.string().c_str(), d.string().c_str());
  return kExitOk;
}

}  // namespace
}  // namespace ausbau

AUSBAU_STAGE_MAIN(kDistfieldBuildStage, DeclareDistfieldBuild, BuildDistanceFields)
