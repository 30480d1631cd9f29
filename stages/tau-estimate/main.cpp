// ausbau-tau-estimate: the threshold tau of InIState planning (thesis
// 5.4.5) and psi (5.4.4) for one scene, from its voxels and labels. See
// README.md beside this file.

#include "cli/stage.h"
#include "collision/fcl_checker.h"
#include "core/log.h"
#include "inistate/inistate_planner.h"
#include "inistate/tau_estimate.h"
#include "scene/scene.h"
#include "workflow/volume_inputs.h"

namespace ausbau {
namespace {

struct TauStageOptions {
  std::string scene;
  std::string output;
  std::string csv;
  std::string validity = "labeled-mliv";
  double psi = 0;
  VolumeInputs volume;
  TauEstimateOptions estimate;
};

int EstimateTauStage(const StageRun& run, const TauStageOptions& options) {
  options.estimate.Check();
  const ValidityMode mode = ParseValidityMode(options.validity);
  if (mode == ValidityMode::kCollision) throw InputError("--validity collision has no tau; pick a volume mode");
  if (!(options.psi >= 0) || !std::isfinite(options.psi)) throw InputError("--psi: must be >= 0");
  const Scene& scene = run.scene;
  const PlanningProblem problem = MakePlanningProblem(scene);
  const std::unique_ptr<VolumeModel> model = LoadVolumeModel(scene, problem, mode, options.volume);
  const double psi = options.psi > 0 ? options.psi : model->EstimatePsi();
  LogInfo("scene %s: validity %s, psi %.6g %s (%s), voxel %.4g %s", scene.name.c_str(), options.validity.c_str(), psi,
          scene.units.c_str(), options.psi > 0 ? "given" : "largest deformable component", model->voxel_size(),
          scene.units.c_str());

  TauArtifact artifact;
  artifact.validity = options.validity;
  artifact.units = scene.units;
  if (mode == ValidityMode::kShrink) {
    // Shrink plans with the shrunk D under plain collision: tau 0.
    artifact.estimate.psi = psi;
    artifact.estimate.solved = true;
    LogInfo("shrink: tau is 0 (D shrunk by %.4g %s)", model->shrink(), scene.units.c_str());
  } else {
    const FclCollisionChecker fcl(problem.robot, problem.environment);
    artifact.estimate =
        EstimateTau(FastenerProblem(problem, fcl, psi), model->volume(), model->measure(), psi, options.estimate);
  }
  WriteTauArtifact(run.output, artifact, run.provenance);
  if (!options.csv.empty()) WriteTauTraceCsv(options.csv, artifact.estimate);
  const TauEstimate& e = artifact.estimate;
  LogInfo("tau %.6g %s^3 (start volume %.6g), psi %.6g %s, %d planning round(s), %zu probes, %.2f s%s; written to %s",
          e.tau, scene.units.c_str(), e.tau_lowest, e.psi, scene.units.c_str(), e.rounds, e.trace.size(), e.seconds,
          e.solved ? "" : " (no round found sigma_1: tau is the last tried)", run.output.c_str());
  return e.solved ? kExitOk : kExitNoPath;
}

}  // namespace
}  // namespace ausbau

int main(int argc, char** argv) {
  using namespace ausbau;
  TauStageOptions options;
  StageDefinition stage(
      "ausbau-tau-estimate",
      "Estimates the intersection-volume threshold tau (and psi) for planning out of an invalid initial state.");
  stage.SceneInput(SceneHash::kWholeScene, &options.scene);
  stage
      .Option("--validity", &options.validity, "shrink | iv | mliv | labeled-mliv | labeled-mliv-unguarded",
              CacheKey::kYes)
      ->check(CLI::IsMember(ValidityModeNames()));
  stage.InputFile("--voxels", &options.volume.voxels, "voxels",
                  "voxels of S and D (ausbau-voxelize); default: voxelized here");
  stage.InputFile("--labels", &options.volume.labels, "labels",
                  "labels of D (ausbau-pbd-label); needed by the labeled modes");
  stage.Option("--rigid-tolerance", &options.volume.rigid_tolerance_mm,
               "labeled-mliv's rigid guard: how deep D's rigid part may touch into S, in mm (scene units converted)",
               CacheKey::kYes);
  stage.Output(&options.output, "tau.h5", kTauSchema, kTauSchemaVersion);
  stage.Option("--csv", &options.csv, "also write the search's trace as CSV", CacheKey::kNo);
  stage.Option("--psi", &options.psi, "scene units; 0 = from the labels (largest deformable component)",
               CacheKey::kYes);
  stage.Seed(&options.estimate.planner.seed);
  stage.Option("--time-limit", &options.estimate.planner.time_limit_s, "seconds per planning round", CacheKey::kYes)
      ->check(TimeLimit());
  stage.Option("--planner", &options.estimate.planner.planner, "local planner of sigma_1 (est, rrt, cr-rrtc, ...)",
               CacheKey::kYes);
  stage.Option("--initial-speed", &options.estimate.initial_speed, "s_init, nodes per reference second",
               CacheKey::kYes);
  stage.Option("--speed-step", &options.estimate.speed_step, "delta_2: target speed increase after a failed round",
               CacheKey::kYes);
  stage.Option("--rounds", &options.estimate.max_rounds, "planning rounds at most", CacheKey::kYes);
  stage.Option("--probe-attempts", &options.estimate.probe_attempts, "expansion attempts per speed probe",
               CacheKey::kYes);
  stage.Threads(&options.estimate.threads);
  return stage.Run(
      argc, argv, [&](const StageRun& run) { return EstimateTauStage(run, options); },
      [&](const StageRun& run) {
        const TauArtifact cached = ReadTauArtifact(run.output);
        LogInfo("%s is up to date (same inputs and options); use --force to estimate again", run.output.c_str());
        if (!options.csv.empty()) WriteTauTraceCsv(options.csv, cached.estimate);
        return cached.estimate.solved ? kExitOk : kExitNoPath;
      });
}
