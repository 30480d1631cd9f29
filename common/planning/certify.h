// Certification of a finished path at a finer step than the planner's.
//
// Planners check edges at a step bound (no vertex of D moves more than
// `step` between checked poses), which leaves thin slivers of collision
// between checked poses undetected. Before a path is returned, every segment
// is re-checked at step / 4, at most 0.25% of D's diagonal
// (CertificationStep); a segment that fails is
// re-planned locally (CR-RRTC between its two end poses, edges checked at
// the fine step, half of its samples near the segment:
// PlanningProblem::sampling_guide) and spliced in. Rare at the thesis's
// step of 1% (a few segments a path at 4%); without it a grazing path can
// fail a later dense check. A validity that measures slack
// (collision/validity.h SlackValidity: rigid-exact) is walked by
// conservative advancement, whose poses do not depend on the step: its
// paths are certified as planned.
#pragma once

#include <chrono>
#include <vector>

#include "planning/planner.h"

namespace ausbau {

struct CertifyReport {
  bool certified = true;
  int repaired_segments = 0;
  // Not certified because the clock (the deadline, or a repair's time
  // limit: safety nets) stopped it, not for want of a repair.
  bool stopped_by_time_limit = false;
};

// The step of the certification: a quarter of the planner's, and never
// coarser than kCertificationResolution of D's diagonal, so that a search
// at a coarser step (`--resolution` above 0.01) returns paths checked as
// finely as one at the thesis's 1%.
constexpr double kCertificationResolution = 0.0025;
double CertificationStep(const PlanningProblem& problem, double planner_step);

// Every segment of `path` is checked at `fine_step` (CertificationStep of
// the planner's step, or finer where a path is certified again). `path` is
// replaced by the certified (possibly repaired) path. `options`
// supplies the seed and the time budget left for repairs. `deadline`: a
// segment walked by conservative advancement past it counts as blocked
// (MotionChecker), so the path is not certified; the straight pulls' safety
// net (planner.h). None by default: a planner's path is always certified
// to its end.
CertifyReport CertifyPath(
    const PlanningProblem& problem, const PoseValidity& validity, double fine_step, const PlannerOptions& options,
    std::vector<Pose>* path,
    std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max());

}  // namespace ausbau
