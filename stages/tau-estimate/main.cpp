// ausbau-tau-estimate: the threshold tau of InIState planning (thesis
// 5.4.5) and psi (5.4.4) for one scene, from its voxels and labels. See
// README.md beside this file.
#include <omp.h>

#include "cli/stage_main.h"
#include "cli/volume_inputs.h"
#include "collision/fcl_checker.h"
#include "core/hash.h"
#include "core/log.h"
#include "inistate/inistate_planner.h"
#include "inistate/tau_estimate.h"
#include "scene/scene.h"

namespace ausbau {
namespace {

struct TauStageOptions {
  std::string scene;
  std::string output = "tau.h5";
  std::string csv;
  std::string validity = "labeled-mliv";
  double psi = 0;
  bool force = false;
  VolumeInputs volume;
  TauEstimateOptions estimate;
};

int Run(TauStageOptions options, const std::string& parameters) {
  options.estimate.Check();
  const ValidityMode mode = ParseValidityMode(options.validity);
  if (mode == ValidityMode::kCollision) throw InputError("--validity collision has no tau; pick a volume mode");
  if (!(options.psi >= 0) || !std::isfinite(options.psi)) throw InputError("--psi: must be >= 0");
  if (options.estimate.threads > 0) omp_set_num_threads(options.estimate.threads);
  const Scene scene = LoadScene(options.scene);
  Provenance provenance{"ausbau-tau-estimate", AUSBAU_VERSION, parameters, {}};
  AddSceneInputs(scene, &provenance);
  AddVolumeInputs(options.volume, &provenance);
  if (!options.force && ExistingProvenanceHash(options.output, kTauSchema, kTauSchemaVersion) == provenance.Hash()) {
    const TauArtifact cached = ReadTauArtifact(options.output);
    LogInfo("%s is up to date (same inputs and options); use --force to estimate again", options.output.c_str());
    if (!options.csv.empty()) WriteTauTraceCsv(options.csv, cached.estimate);
    return cached.estimate.solved ? kExitOk : kExitNoPath;
  }
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
  WriteTauArtifact(options.output, artifact, provenance);
  if (!options.csv.empty()) WriteTauTraceCsv(options.csv, artifact.estimate);
  const TauEstimate& e = artifact.estimate;
  LogInfo("tau %.6g %s^3 (start volume %.6g), psi %.6g %s, %d planning round(s), %zu probes, %.2f s%s; written to %s",
          e.tau, scene.units.c_str(), e.tau_lowest, e.psi, scene.units.c_str(), e.rounds, e.trace.size(), e.seconds,
          e.solved ? "" : " (no round found sigma_1: tau is the last tried)", options.output.c_str());
  return e.solved ? kExitOk : kExitNoPath;
}

}  // namespace
}  // namespace ausbau

int main(int argc, char** argv) {
  using namespace ausbau;
  TauStageOptions options;
  CLI::App* app_ptr = nullptr;
  return RunStage(
      {"ausbau-tau-estimate",
       "Estimates the intersection-volume threshold tau (and psi) for planning out of an invalid initial state."},
      argc, argv,
      [&](CLI::App& app) {
        app_ptr = &app;
        app.add_option("--scene", options.scene, "scene.yaml")->required();
        app.add_option("--validity", options.validity, "shrink | iv | mliv | labeled-mliv | labeled-mliv-unguarded")
            ->check(CLI::IsMember(ValidityModeNames()))
            ->capture_default_str();
        app.add_option("--voxels", options.volume.voxels, "voxels of S and D (ausbau-voxelize); default: voxelized here");
        app.add_option("--labels", options.volume.labels, "labels of D (ausbau-pbd-label); needed by the labeled modes");
        app.add_option("--rigid-tolerance", options.volume.rigid_tolerance_mm,
                       "labeled-mliv's rigid guard: how deep D's rigid part may touch into S, in mm (scene units "
                       "converted)")
            ->capture_default_str();
        app.add_option("-o,--output", options.output, "tau artifact (HDF5, schema ausbau-tau)")->capture_default_str();
        app.add_option("--csv", options.csv, "also write the search's trace as CSV");
        app.add_option("--psi", options.psi, "scene units; 0 = from the labels (largest deformable component)")
            ->capture_default_str();
        app.add_option("--seed", options.estimate.planner.seed, "random seed of the probes and rounds")
            ->capture_default_str()->check(NonNegative());
        app.add_option("--time-limit", options.estimate.planner.time_limit_s, "seconds per planning round")
            ->capture_default_str()->check(TimeLimit());
        app.add_option("--planner", options.estimate.planner.planner, "local planner of sigma_1 (est, rrt, cr-rrtc, ...)")
            ->capture_default_str();
        app.add_option("--initial-speed", options.estimate.initial_speed, "s_init, nodes per reference second")
            ->capture_default_str();
        app.add_option("--speed-step", options.estimate.speed_step,
                       "delta_2: target speed increase after a failed round")
            ->capture_default_str();
        app.add_option("--rounds", options.estimate.max_rounds, "planning rounds at most")->capture_default_str();
        app.add_option("--probe-attempts", options.estimate.probe_attempts, "expansion attempts per speed probe")
            ->capture_default_str();
        app.add_option("--threads", options.estimate.threads, "parallel probes; 0 = all cores")->capture_default_str()->check(ThreadCount());
        app.add_flag("--force", options.force, "estimate even when the output is up to date");
      },
      [&] { return Run(options, OptionsYaml(*app_ptr, {"scene", "output", "csv", "force", "threads", "voxels", "labels"})); });
}
