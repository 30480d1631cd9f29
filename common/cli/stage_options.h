// The options of the library's option structs, declared once for every
// stage that takes them (as COLMAP's OptionManager does): a flag then means
// the same in each stage, its help text is written once, and a stage's main
// names a group instead of repeating its declarations.
#pragma once

#include "cli/stage.h"
#include "inistate/tau_estimate.h"
#include "planning/smoother.h"
#include "workflow/label_part.h"
#include "workflow/part_spheres.h"
#include "workflow/plan_scene.h"
#include "workflow/volume_inputs.h"

namespace ausbau {

// The time budget of a stage that can run long (plan, smooth, tau-estimate):
// --budget S (seconds from the stage's start) or --deadline T (seconds since
// the Unix epoch; what pipelines/inistate.mk passes, so that all stages of a
// run share one end). Never in the cache key: the budget changes when the
// work stops, not what it computes. Deadline(): the earlier of the two, 0
// for none.
struct TimeBudgetOptions {
  double budget_s = 0;
  double deadline = 0;
  double started = 0;  // epoch seconds when the options were made
  TimeBudgetOptions();
  double Deadline() const;
};
void AddTimeBudgetOptions(StageDefinition& stage, TimeBudgetOptions* budget);

// --planner, --sampler, --sigma, --time-limit, --max-iterations, --u,
// --range-max, --resolution, --threads, --seed.
void AddPlannerOptions(StageDefinition& stage, PlannerOptions* planner);

// --voxels, --labels (input files of the volume validity modes) and
// --rigid-tolerance (the rigid guard, mm).
void AddVolumeInputOptions(StageDefinition& stage, VolumeInputs* volume);

// ausbau-plan's: the planner, --collision, --validity, --tau, --tau-file,
// --psi, --rigid-planner, --distfield, the volume inputs, --no-verify.
void AddPlanSceneOptions(StageDefinition& stage, PlanSceneOptions* plan);

// ausbau-smooth's: --seed, --attempts, --time-limit, --resolution.
void AddSmoothOptions(StageDefinition& stage, SmoothOptions* smooth);

// ausbau-tau-estimate's search: --seed, --time-limit, --planner,
// --initial-speed, --speed-step, --rounds, --probe-attempts, --threads.
void AddTauEstimateOptions(StageDefinition& stage, TauEstimateOptions* estimate);

// ausbau-medial-spheres's: --threads, --delta, --push-factor,
// --cooling-iterations, --growth-iterations, --weld-tolerance.
void AddPartSpheresOptions(StageDefinition& stage, PartSpheresOptions* options);

// ausbau-pbd-label's: --rule, --rigid-tolerance, --weld-tolerance and the
// simulation's (--threads, --measure, --kappa, ..., --refine).
void AddLabelPartOptions(StageDefinition& stage, LabelPartOptions* label);

}  // namespace ausbau
