// ausbau-scene-check: what a scene contains and what in it is suspicious,
// before any planning. The checks are in common/scene/scene_check.h; see
// README.md beside this file.
#include <cstdio>

#include "cli/stage.h"
#include "core/atomic_file.h"
#include "core/format.h"
#include "scene/scene.h"
#include "scene/scene_check.h"
#include "workflow/installed_check.h"

namespace ausbau {
namespace {

constexpr StageSpec kSceneCheckStage{
    "ausbau-scene-check",
    "Prints what a scene contains and what in it is suspicious (units, poses, meshes).",
    SceneHash::kWholeScene,
    {},  // no artifact: the summary goes to stdout (and --json)
    {}};

struct SceneCheckOptions {
  std::string json;     // empty: no JSON file
  bool strict = false;  // exit 1 when any finding is a warning
  InstalledCheckOptions installed;
  bool no_installed = false;  // skip the look at the installed pose (measured: can take seconds)
};

void DeclareCheck(StageDefinition& stage, SceneCheckOptions* options) {
  stage.ExtraOutput("--json", &options->json, "also write the summary and the findings as JSON (atomically)");
  stage.Flag("--strict", &options->strict, "exit 1 when any finding is a warning", CacheKey::kNo);
  stage.Option("--rigid-tolerance", &options->installed.rigid_tolerance_mm,
               "at the installed pose: how deep D may touch into S and still be in contact, in mm (converted by "
               "the scene's units), as the planning stages take it",
               CacheKey::kNo);
  stage.Option("--resolution", &options->installed.resolution,
               "the planner's edge check step, a fraction of D's box diagonal (fits finer than it are reported)",
               CacheKey::kNo);
  stage.Flag("--no-installed", &options->no_installed,
             "skip the measured look at the installed pose (contacts, fits, clashes, fasteners)", CacheKey::kNo);
}

int Check(const StageRun& run, const SceneCheckOptions& options) {
  SceneSummary summary = CheckScene(run.scene);
  if (!options.no_installed) {
    for (SceneFinding& finding : CheckInstalledPose(run.scene, options.installed))
      summary.findings.push_back(std::move(finding));
  }
  // Names in it come from files (the scene's, its parts'): shown, never sent raw.
  std::fputs(TerminalSafeLines(SceneSummaryText(summary)).c_str(), stdout);
  std::fflush(stdout);
  if (!options.json.empty()) WriteTextFileAtomically(options.json, SceneSummaryJson(summary));
  // --strict is for scripts that want to stop on a suspicious scene; 1 is the code left free by bad input (2).
  if (options.strict && summary.WarningCount() > 0) return 1;
  return kExitOk;
}

}  // namespace
}  // namespace ausbau

AUSBAU_STAGE_MAIN(kSceneCheckStage, DeclareCheck, Check)
