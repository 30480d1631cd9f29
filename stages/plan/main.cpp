// ausbau-plan: rigid-body planning for one scene, from the start pose to the
// goal pose or, without a goal, out of S (disassembly). The work is
// workflow/plan_scene.h; see README.md beside this file.
#include <cstdio>

#include "cli/stage.h"
#include "core/hash.h"
#include "core/log.h"
#include "inistate/tau_estimate.h"
#include "planning/path_io.h"
#include "workflow/plan_scene.h"

namespace ausbau {
namespace {

struct PlanStageOptions {
  std::string scene;
  std::string output;
  std::string csv;
  std::string ompl_path;
  bool choose_validity = false;  // print the validity this scene needs, plan nothing
  PlanSceneOptions plan;
};

void WriteExtras(const PlanStageOptions& options, const PathArtifact& artifact) {
  if (!artifact.success) return;
  if (!options.csv.empty()) WritePathCsv(options.csv, artifact.waypoints);
  if (!options.ompl_path.empty()) WriteOmplPath(options.ompl_path, artifact.waypoints);
}

int Plan(const StageRun& run, const PlanStageOptions& options) {
  const PlannedPath planned = PlanScene(run.scene, options.plan);
  WritePathArtifact(run.output, planned.artifact, run.provenance);
  WriteExtras(options, planned.artifact);
  if (!planned.artifact.success) return kExitNoPath;
  LogInfo("path: %zu waypoints, length %.4f (normalized), written to %s%s%s", planned.artifact.waypoints.size(),
          planned.artifact.length_normalized, run.output.c_str(), options.csv.empty() ? "" : " and ",
          options.csv.c_str());
  return kExitOk;
}

// An existing output with the same provenance is the same answer: reused
// (its CSV and OMPL files written again), and its exit status returned.
int Reuse(const StageRun& run, const PlanStageOptions& options) {
  const PathArtifact cached = ReadPathArtifact(run.output);
  LogInfo("%s is up to date (same inputs and options); use --force to plan again", run.output.c_str());
  WriteExtras(options, cached);
  return cached.success ? kExitOk : kExitNoPath;
}

// --choose-validity: the pipeline's VALIDITY=auto asks this before it runs
// any stage.
int PrintValidity(const StageRun& run, const PlanStageOptions& options) {
  std::printf("%s\n", ChooseValidity(run.scene, options.plan.volume.rigid_tolerance_mm).c_str());
  return kExitOk;
}

}  // namespace
}  // namespace ausbau

int main(int argc, char** argv) {
  using namespace ausbau;
  PlanStageOptions options;
  PlanSceneOptions& plan = options.plan;
  PlannerOptions& planner = plan.planner;
  StageDefinition stage("ausbau-plan",
                        "Plans a collision-free motion of the part D out of (or through) its surroundings S.");
  stage.SceneInput(SceneHash::kWholeScene, &options.scene);
  stage.Option("--planner", &planner.planner,
               "rrt | rrtc | cr-rrtc | est | prm; auto = cr-rrtc, or est for sigma_1 in volume modes", CacheKey::kYes);
  stage.Option("--sampler", &planner.sampler, "uniform | gaussian | bridge | mixed", CacheKey::kYes);
  stage.Option("--sigma", &planner.sampler_sigma,
               "gaussian/bridge deviation as a fraction of D's diagonal; 0 = automatic (0.25)", CacheKey::kYes);
  stage.Threads(&planner.threads);
  stage.Seed(&planner.seed);
  stage.Option("--time-limit", &planner.time_limit_s, "seconds", CacheKey::kYes)->check(TimeLimit());
  stage.Option("--max-iterations", &planner.max_iterations, "0 = unlimited", CacheKey::kYes);
  stage.Option("--u", &planner.u, "rrtc: metric weight of translation, (0, 1)", CacheKey::kYes);
  stage.Option("--range-max", &planner.range_max, "rrtc: maximal edge range, (0, 1]", CacheKey::kYes);
  stage.Option("--resolution", &planner.resolution, "edge check step as a fraction of D's AABB diagonal",
               CacheKey::kYes);
  stage.Output(&options.output, "path.h5", kPathSchema, kPathSchemaVersion);
  stage.Option("--csv", &options.csv, "also write the path as CSV (x,y,z,qw,qx,qy,qz)", CacheKey::kNo);
  stage.Option("--ompl-path", &options.ompl_path, "also write the path in OMPL's format (x y z qx qy qz qw)",
               CacheKey::kNo);
  stage.Flag("!--no-verify", &plan.verify, "skip the dense re-check of the result", CacheKey::kNo);
  stage.Flag("--choose-validity", &options.choose_validity,
             "print the --validity this scene needs (rigid-exact, or labeled-mliv where an installed interference is "
             "not measured) and exit; the pipeline's VALIDITY=auto",
             CacheKey::kNo);
  stage
      .Option("--collision", &plan.collision, "fcl | farr (FARR rays in front of FCL, same answers; docs/farr.md)",
              CacheKey::kYes)
      ->check(CLI::IsMember({"fcl", "farr"}));
  stage
      .Option("--validity", &plan.validity,
              "rigid-exact | collision | shrink | iv | mliv | labeled-mliv | labeled-mliv-unguarded (all but "
              "collision: the start may collide; docs/inistate.md, docs/rigid-exact.md)",
              CacheKey::kYes)
      ->check(CLI::IsMember(PlanValidityNames()));
  stage.Option("--rigid-tolerance", &plan.volume.rigid_tolerance_mm,
               "rigid-exact, and labeled-mliv's rigid guard: how deep D's rigid part may touch into S, in mm "
               "(converted by the scene's units)",
               CacheKey::kYes);
  stage.app()
      .add_option("--tau", plan.tau,
                  "volume threshold, scene units^3; default: from --tau-file, else estimated (shrink: 0)")
      ->check(NonNegative());
  stage.InputFile("--tau-file", &plan.tau_file, "tau", "tau and psi from ausbau-tau-estimate (HDF5)");
  stage.app().add_option("--psi", plan.psi,
                         "sigma_1 ends when distance(S, D) > psi, scene units; default: from --tau-file or the labels");
  stage.InputFile("--voxels", &plan.volume.voxels, "voxels",
                  "voxels of S and D (ausbau-voxelize); default: voxelized here");
  stage.InputFile("--labels", &plan.volume.labels, "labels",
                  "labels of D (ausbau-pbd-label); needed by the labeled modes");
  stage.Option("--rigid-planner", &plan.rigid_planner, "planner of sigma_2 (volume modes), collision-checked",
               CacheKey::kYes);
  stage.Option("--distfield", &plan.distfield,
               "farr: distance fields S.h5,D.h5 (ausbau-distfield-build); default: built or reused through the "
               "cache (<scene dir>/.ausbau-cache or $AUSBAU_CACHE_DIR)",
               CacheKey::kNo);
  // The two distance-field files, by content (one option names both).
  stage.AddInputs([&](Provenance* provenance) {
    const std::vector<std::string> distfield = DistfieldPaths(plan);
    if (distfield.empty()) return;
    provenance->inputs.emplace_back("distfield-static", HashFile(distfield[0]));
    provenance->inputs.emplace_back("distfield-dynamic", HashFile(distfield[1]));
  });
  return stage.Run(
      argc, argv,
      [&](const StageRun& run) { return options.choose_validity ? PrintValidity(run, options) : Plan(run, options); },
      [&](const StageRun& run) { return options.choose_validity ? PrintValidity(run, options) : Reuse(run, options); });
}
