// ausbau-distfield-build: the FARR distance fields of a scene (thesis 4.2.2),
// one for S (all static meshes merged, world coordinates) and one for D (in
// the planning convention: D's mesh relative to its reference point), as
// ausbau-distfield artifacts. See README.md beside this file.
#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include "artifact/artifact.h"
#include "cli/stage_main.h"
#include "collision/distance_field.h"
#include "core/log.h"
#include "planning/state_space.h"
#include "scene/scene.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

struct DistfieldBuildOptions {
  std::string scene;
  std::string output_dir;  // -o DIR: DIR/distfield-static.h5, DIR/distfield-dynamic.h5
  std::string static_out;  // or both files explicitly
  std::string dynamic_out;
  double memory_budget_gib = 4.0;
  bool force = false;
  DistanceFieldOptions field;
};

// One field: up to date at `target` (same provenance), copied from the cache,
// or built (and then written to `target` and, when it is another file, the
// cache). Returns the target.
fs::path MakeField(const TriangleMesh& mesh, const DistfieldBuildOptions& options, const fs::path& cache_dir,
                   const fs::path& explicit_target, const std::string& name, const std::string& units,
                   const std::string& frame) {
  const std::string mesh_hash = MeshContentHash(mesh);
  const std::string expected =
      DistanceFieldProvenanceHash({mesh_hash, options.field.resolution, options.field.padding});
  const fs::path cached = DistanceFieldCachePath(cache_dir, mesh_hash, options.field.resolution);
  const fs::path target = explicit_target.empty() ? cached : explicit_target;
  PlanDistanceField(mesh, options.field);  // the memory guard, before any work
  if (!options.force && ExistingProvenanceHash(target, kDistanceFieldSchema, kDistanceFieldSchemaVersion) == expected) {
    LogInfo("%s: %s is up to date (same mesh and resolution); use --force to build again", name.c_str(),
            target.string().c_str());
    return target;
  }
  if (!options.force && target != cached &&
      ExistingProvenanceHash(cached, kDistanceFieldSchema, kDistanceFieldSchemaVersion) == expected) {
    // Copy the cached file (atomically: a temporary beside the target, then rename).
    if (!target.parent_path().empty()) fs::create_directories(target.parent_path());
    const fs::path temporary = target.string() + ".tmp-" + std::to_string(::getpid());
    fs::copy_file(cached, temporary, fs::copy_options::overwrite_existing);
    fs::rename(temporary, target);
    LogInfo("%s: copied from the cache %s", name.c_str(), cached.string().c_str());
    return target;
  }
  const auto field = BuildDistanceField(mesh, options.field, name);
  WriteDistanceField(target, *field, units, frame);
  LogInfo("%s: %d x %d x %d cells (cell %g %s), written to %s", name.c_str(), field->dims()[0], field->dims()[1],
          field->dims()[2], field->spacing(), units.empty() ? "units" : units.c_str(), target.string().c_str());
  if (target != cached) {
    try {
      fs::create_directories(cache_dir);
      WriteDistanceField(cached, *field, units, frame);
    } catch (const std::exception& e) {
      LogWarn("%s: cannot write the cache file %s (%s)", name.c_str(), cached.string().c_str(), e.what());
    }
  }
  return target;
}

int Run(DistfieldBuildOptions options) {
  if (!(options.memory_budget_gib > 0)) throw InputError("--memory-limit: must be > 0 GiB");
  options.field.memory_budget_bytes = static_cast<std::uint64_t>(options.memory_budget_gib * double(1 << 30));
  options.field.Check();
  if (!options.output_dir.empty() && (!options.static_out.empty() || !options.dynamic_out.empty())) {
    throw InputError("--output-dir: give either --output-dir DIR or --static-out and --dynamic-out, not both");
  }
  if (options.static_out.empty() != options.dynamic_out.empty()) {
    throw InputError("--static-out and --dynamic-out: give both or neither");
  }
  fs::path static_target = options.static_out, dynamic_target = options.dynamic_out;
  if (!options.output_dir.empty()) {
    static_target = fs::path(options.output_dir) / "distfield-static.h5";
    dynamic_target = fs::path(options.output_dir) / "distfield-dynamic.h5";
  }
  const Scene scene = LoadScene(options.scene);
  const PlanningProblem problem = MakePlanningProblem(scene);
  const fs::path cache_dir = DefaultDistanceFieldCacheDir(scene.file);
  LogInfo("scene %s: S %zu triangles, D %zu triangles, resolution %d, cache %s", scene.name.c_str(),
          problem.environment.triangles.size(), problem.robot.triangles.size(), options.field.resolution,
          cache_dir.string().c_str());
  const fs::path s =
      MakeField(problem.environment, options, cache_dir, static_target, "distance field of S", scene.units, "world");
  const fs::path d = MakeField(problem.robot, options, cache_dir, dynamic_target, "distance field of D", scene.units,
                               "D relative to its reference point");
  // Machine-readable: the two files, as --distfield of ausbau-plan takes them.
  std::printf("%s,%s\n", s.string().c_str(), d.string().c_str());
  return kExitOk;
}

}  // namespace
}  // namespace ausbau

int main(int argc, char** argv) {
  using namespace ausbau;
  DistfieldBuildOptions options;
  return RunStage(
      {"ausbau-distfield-build",
       "Builds the FARR distance fields of S and D (thesis 4.2.2) for ausbau-plan --collision farr."},
      argc, argv,
      [&](CLI::App& app) {
        app.add_option("--scene", options.scene, "scene.yaml")->required();
        app.add_option("--field-cells", options.field.resolution, "cells along the longest axis of 1.3x the AABB")
            ->capture_default_str();
        app.add_option("--threads", options.field.threads, "OpenMP threads; 0 = all cores")
            ->capture_default_str()
            ->check(ThreadCount());
        app.add_option("--memory-limit", options.memory_budget_gib, "GiB; larger fields are refused")
            ->capture_default_str();
        app.add_option("--output-dir", options.output_dir,
                       "write DIR/distfield-static.h5 and DIR/distfield-dynamic.h5 (default: the cache)");
        app.add_option("--static-out", options.static_out, "the field of S (with --dynamic-out)");
        app.add_option("--dynamic-out", options.dynamic_out, "the field of D (with --static-out)");
        AddRenamedFlag(app, "--resolution", "--field-cells");
        AddRenamedFlag(app, "--memory-budget", "--memory-limit");
        app.add_flag("--force", options.force, "build even when the output is up to date");
      },
      [&] { return Run(options); });
}
