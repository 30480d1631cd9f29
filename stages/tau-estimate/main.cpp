// ausbau-tau-estimate: the threshold tau of InIState planning (thesis
// 5.4.5) and psi (5.4.4) for one scene, from its voxels and labels. The
// work is workflow/scene_tau.h; see README.md beside this file.
#include "artifact/run_files.h"
#include "cli/stage_options.h"
#include "core/log.h"
#include "workflow/scene_tau.h"

namespace ausbau {
namespace {

constexpr StageSpec kTauEstimateStage{
    "ausbau-tau-estimate",
    "Estimates the intersection-volume threshold tau (and psi) for planning out of an invalid initial state.",
    SceneHash::kWholeScene,
    {kRunFileTau, kTauSchema, kTauSchemaVersion},
    {"inputs and options", "estimate again"}};

struct TauStageOptions {
  std::string csv;
  SceneTauOptions tau;
  TimeBudgetOptions budget;
};

void DeclareTau(StageDefinition& stage, TauStageOptions* options) {
  stage.ExtraOutput("--csv", &options->csv, "also write the search's trace as CSV");
  stage.Choice("--validity", &options->tau.validity, InIStateValidityNames(), ParseValidityMode, ValidityModeName,
               "shrink | iv | mliv | labeled-mliv | labeled-mliv-unguarded", CacheKey::kYes);
  stage.Option("--psi", &options->tau.psi,
               "mm (converted by the scene's units); 0 = from the labels (largest deformable component)",
               CacheKey::kYes);
  AddVolumeInputOptions(stage, &options->tau.volume);
  AddTauEstimateOptions(stage, &options->tau.estimate);
  AddTimeBudgetOptions(stage, &options->budget);
}

int EstimateTauStage(const StageRun& run, const TauStageOptions& options) {
  SceneTauOptions tau = options.tau;
  tau.estimate.deadline = options.budget.Deadline();
  const TauArtifact artifact = EstimateSceneTau(run.scene, tau);
  WriteTauArtifact(run.output, artifact, run.provenance);
  if (!options.csv.empty()) WriteTauTraceCsv(options.csv, artifact.estimate);
  const TauEstimate& e = artifact.estimate;
  const char* units = run.scene.units.c_str();
  LogInfo("tau %.6g %s^3 (start volume %.6g), psi %.6g %s, %d planning round(s), %zu probes, %.2f s%s%s; written to %s",
          e.tau, units, e.tau_lowest, e.psi, units, e.rounds, e.trace.size(), e.seconds,
          e.solved ? "" : " (no round found sigma_1: tau is the last tried)",
          e.cut_short ? " (cut short by the clock: not the deterministic estimate)" : "", run.output.c_str());
  return e.solved ? kExitOk : kExitNoPath;
}

int ReuseTau(const StageRun& run, const TauStageOptions& options) {
  const TauArtifact cached = ReadTauArtifact(run.output);
  if (!options.csv.empty()) WriteTauTraceCsv(options.csv, cached.estimate);
  return cached.estimate.solved ? kExitOk : kExitNoPath;
}

// An estimate a clock cut short (a round's --time-limit, a safety net, or
// the budget) is not the deterministic one: estimated again, not reused.
bool CutShort(const StageRun& run, const TauStageOptions&) {
  if (!ReadTauArtifact(run.output).estimate.cut_short) return false;
  LogInfo("%s was cut short by the clock: estimating again", run.output.c_str());
  return true;
}

}  // namespace
}  // namespace ausbau

AUSBAU_STAGE_MAIN(kTauEstimateStage, DeclareTau, EstimateTauStage, ReuseTau, CutShort)
