// ausbau-plan: rigid-body planning for one scene, from the start pose to the
// goal pose or, without a goal, out of S (disassembly). The work is
// workflow/plan_scene.h; see README.md beside this file.
#include <cstdio>

#include "artifact/run_files.h"
#include "cli/stage_options.h"
#include "core/log.h"
#include "planning/path_io.h"
#include "workflow/plan_scene.h"

namespace ausbau {
namespace {

constexpr StageSpec kPlanStage{"ausbau-plan",
                               "Plans a collision-free motion of the part D out of (or through) its surroundings S.",
                               SceneHash::kWholeScene,
                               {kRunFilePath, kPathSchema, kPathSchemaVersion},
                               {"inputs and options", "plan again"}};

struct PlanStageOptions {
  std::string csv;
  std::string ompl_path;
  PlanSceneOptions plan;
  TimeBudgetOptions budget;
};

// --choose-validity: the pipeline's VALIDITY=auto asks this before it runs
// any stage.
int PrintValidity(const StageRun& run, const PlanStageOptions& options) {
  std::printf("%s\n", ValidityModeName(ChooseValidity(run.scene, options.plan.volume.rigid_tolerance_mm)).c_str());
  return kExitOk;
}

void DeclarePlan(StageDefinition& stage, PlanStageOptions* options) {
  stage.ExtraOutput("--csv", &options->csv, "also write the path as CSV (x,y,z,qw,qx,qy,qz)");
  stage.ExtraOutput("--ompl-path", &options->ompl_path, "also write the path in OMPL's format (x y z qx qy qz qw)");
  AddPlanSceneOptions(stage, &options->plan);
  AddTimeBudgetOptions(stage, &options->budget);
  stage.Query("--choose-validity",
              "print the --validity this scene needs (rigid-exact, or labeled-mliv where an installed interference is "
              "not measured) and exit; the pipeline's VALIDITY=auto",
              [options](const StageRun& run) { return PrintValidity(run, *options); });
}

void WriteExtras(const PlanStageOptions& options, const PathArtifact& artifact) {
  if (!artifact.success) return;
  if (!options.csv.empty()) WritePathCsv(options.csv, artifact.waypoints);
  if (!options.ompl_path.empty()) WriteOmplPath(options.ompl_path, artifact.waypoints);
}

int Plan(const StageRun& run, const PlanStageOptions& options) {
  PlanSceneOptions plan = options.plan;
  plan.deadline = options.budget.Deadline();
  plan.planner.progress = ShowSearchProgress(
      "planning", LimitByDeadline(plan.planner.time_limit_s, plan.deadline, 0.5, nullptr), "iterations");
  const PlannedPath planned = PlanScene(run.scene, plan);
  WritePathArtifact(run.output, planned.artifact, run.provenance);
  WriteExtras(options, planned.artifact);
  if (!planned.artifact.success) return kExitNoPath;
  LogInfo("path: %zu waypoints, length %.4f (normalized), written to %s%s%s", planned.artifact.waypoints.size(),
          planned.artifact.length_normalized, run.output.c_str(), options.csv.empty() ? "" : " and ",
          options.csv.c_str());
  return kExitOk;
}

// An existing output with the same provenance is the same answer: reused
// (its CSV and OMPL files written again), and its exit status returned;
// unless the time budget ended that search (CutShort): then this run plans
// again.
bool CutShort(const StageRun& run, const PlanStageOptions&) {
  if (!ReadPathArtifact(run.output).stopped_by_budget) return false;
  LogInfo("%s was cut short by its time budget: planning again", run.output.c_str());
  return true;
}

int Reuse(const StageRun& run, const PlanStageOptions& options) {
  const PathArtifact cached = ReadPathArtifact(run.output);
  WriteExtras(options, cached);
  return cached.success ? kExitOk : kExitNoPath;
}

}  // namespace
}  // namespace ausbau

AUSBAU_STAGE_MAIN(kPlanStage, DeclarePlan, Plan, Reuse, CutShort)
