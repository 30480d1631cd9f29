// ausbau-verdict: the answer of a run for one scene - is D removable, where
// along the path is the largest (Labeled-)MLIV, what blocks D, how long did
// the stages take - as verdict.json (schemas/verdict.md) and a short summary
// on stdout. The work is workflow/verdict.h; see README.md beside this file.
#include <cmath>
#include <cstdio>

#include "artifact/run_files.h"
#include "cli/stage.h"
#include "core/atomic_file.h"
#include "workflow/verdict.h"

namespace ausbau {
namespace {

// No artifact: the verdict is JSON (-o), always written anew.
constexpr StageSpec kVerdictStage{"ausbau-verdict",
                                  "Says whether D is removable and summarizes an InIState run as verdict.json.",
                                  SceneHash::kWholeScene,
                                  {},
                                  {}};

struct VerdictStageOptions {
  std::string output = kRunFileVerdict;
  VerdictInputs inputs;
};

void DeclareVerdict(StageDefinition& stage, VerdictStageOptions* options) {
  VerdictInputs& inputs = options->inputs;
  stage.InputFile("--path", &inputs.path, "path", "the final path artifact (ausbau-path), e.g. path-smooth.h5")
      ->required();
  stage.InputFile("--tau-file", &inputs.tau, "tau", "tau artifact (ausbau-tau-estimate)");
  AddRenamedFlag(stage.app(), "--tau", "--tau-file");
  stage.Option("--times", &inputs.times, "folder of <stage>.seconds files (scripts/timed.sh)", CacheKey::kNo);
  stage.Option("--budget", &inputs.budget, "seconds; adds within_budget (total <= budget)", CacheKey::kNo)
      ->check(CLI::NonNegativeNumber);
  // Read and recorded by the work itself (the verdict is always written anew): not hashed.
  stage.InputFile("--csv-name", &inputs.csv, "",
                  "the path's CSV file: checked exactly as written (plain interpolation) and recorded");
  stage.Option("--rigid-tolerance", &inputs.rigid_tolerance_mm,
               "how deep D's rigid part may touch into S along the path, in mm (scene units converted)", CacheKey::kNo);
  stage.ExtraOutput("-o,--output", &options->output, "verdict (JSON, schemas/verdict.md)");
}

int Judge(const StageRun& run, const VerdictStageOptions& options) {
  if (!std::isfinite(options.inputs.budget)) throw InputError("--budget: must be a finite number");
  VerdictInputs inputs = options.inputs;
  inputs.progress = ShowProgress("exact check, segments");
  const Verdict verdict = JudgeRun(run.scene, inputs);
  WriteTextFileAtomically(options.output, VerdictJson(verdict));
  PrintVerdictSummary(verdict, options.output, stdout);
  return verdict.removable ? kExitOk : kExitNoPath;
}

}  // namespace
}  // namespace ausbau

AUSBAU_STAGE_MAIN(kVerdictStage, DeclareVerdict, Judge)
