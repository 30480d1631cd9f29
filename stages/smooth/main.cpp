// ausbau-smooth: shortcut smoothing of a planned path under the same
// validity check; never returns a path that fails the dense re-check. The
// work is workflow/smooth_path.h; see README.md beside this file.
#include <filesystem>

#include "artifact/run_files.h"
#include "cli/stage_options.h"
#include "core/log.h"
#include "planning/path_io.h"
#include "workflow/path_profile.h"
#include "workflow/smooth_path.h"

namespace ausbau {
namespace {

constexpr StageSpec kSmoothStage{
    "ausbau-smooth",
    "Shortens a planned path by shortcuts that keep it valid (collision-free, or within its InIState volume).",
    SceneHash::kWholeScene,
    {kRunFilePathSmooth, kPathSchema, kPathSchemaVersion},
    {"inputs and options", "smooth again"}};

struct SmoothStageOptions {
  std::string path;
  std::string csv;
  std::string profile;  // intersection and clearance profile (CSV)
  SmoothPlannedPathOptions smooth;
  TimeBudgetOptions budget;
};

void DeclareSmooth(StageDefinition& stage, SmoothStageOptions* options) {
  stage.InputFile("--path", &options->path, "path", "path artifact from ausbau-plan")->required();
  stage.ExtraOutput("--csv", &options->csv, "also write the path as CSV (x,y,z,qw,qx,qy,qz)");
  stage.ExtraOutput("--profile", &options->profile,
                    "also write the intersection and clearance profile along the path (CSV with units and poses)");
  AddSmoothOptions(stage, &options->smooth.smooth);
  AddTimeBudgetOptions(stage, &options->budget);
  AddVolumeInputOptions(stage, &options->smooth.volume);
}

int Smooth(const StageRun& run, const SmoothStageOptions& options) {
  options.smooth.smooth.Check();
  const PathArtifact input = ReadPathArtifact(options.path);
  const PlanningProblem problem = MakePlanningProblemHolding(run.scene, input.waypoints);
  // Within the time budget: smoothing stops early with a shorter path so
  // far (every shortcut it keeps is checked), never a worse one.
  SmoothPlannedPathOptions smooth = options.smooth;
  bool bound = false;
  smooth.smooth.time_limit_s = LimitByDeadline(smooth.smooth.time_limit_s, options.budget.Deadline(), 0.1, &bound);
  if (bound) LogInfo("time budget: %.1f s left for smoothing", smooth.smooth.time_limit_s);
  smooth.smooth.progress = ShowProgress("smoothing");
  const SmoothedPath smoothed = SmoothPlannedPath(run.scene, problem, input, options.path, smooth);
  WritePathArtifact(run.output, smoothed.artifact, run.provenance);
  if (!options.csv.empty()) WritePathCsv(options.csv, smoothed.artifact.waypoints);
  if (!options.profile.empty()) {
    WritePathProfile(options.profile, problem, smoothed.result.path, smoothed.model.get(), smoothed.clearance_robot,
                     run.scene.units);
  }
  LogInfo("written to %s%s%s%s%s", run.output.c_str(), options.csv.empty() ? "" : ", ", options.csv.c_str(),
          options.profile.empty() ? "" : ", ", options.profile.c_str());
  return kExitOk;
}

// Up to date: the CSV again, and the profile where it is missing.
int Reuse(const StageRun& run, const SmoothStageOptions& options) {
  const PathArtifact cached = ReadPathArtifact(run.output);
  if (!options.csv.empty()) WritePathCsv(options.csv, cached.waypoints);
  if (!options.profile.empty() && !std::filesystem::exists(options.profile)) {
    const PlanningProblem problem = MakePlanningProblemHolding(run.scene, cached.waypoints);
    std::unique_ptr<VolumeModel> model;
    if (IsVolumeValidity(cached.validity)) {
      model = LoadVolumeModel(run.scene, problem, cached.validity, options.smooth.volume);
    }
    std::vector<Pose> path;
    for (const Pose& pose : cached.waypoints) path.push_back(problem.SceneToPlanning(pose));
    WritePathProfile(options.profile, problem, path, model.get(),
                     PathClearanceRobot(run.scene, problem, cached.validity, options.smooth.volume.rigid_tolerance_mm),
                     run.scene.units);
  }
  return kExitOk;
}

// A smoothing its time limit (a safety net) or budget cut short is not the
// deterministic answer: smoothed again rather than reused.
bool CutShort(const StageRun& run, const SmoothStageOptions&) {
  if (!ReadPathArtifact(run.output).smoothing_cut_short) return false;
  LogInfo("%s was cut short by its time limit: smoothing again", run.output.c_str());
  return true;
}

}  // namespace
}  // namespace ausbau

AUSBAU_STAGE_MAIN(kSmoothStage, DeclareSmooth, Smooth, Reuse, CutShort)
