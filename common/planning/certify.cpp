#include "planning/certify.h"

#include <algorithm>

#include "core/log.h"
#include "planning/rrt_connect.h"

namespace ausbau {

double CertificationStep(const PlanningProblem& problem, double planner_step) {
  return std::min(planner_step / 4.0, kCertificationResolution * problem.robot_diagonal);
}

CertifyReport CertifyPath(const PlanningProblem& problem, const PoseValidity& validity, double fine_step,
                          const PlannerOptions& options, std::vector<Pose>* path,
                          std::chrono::steady_clock::time_point deadline) {
  CertifyReport report;
  // A validity that measures slack is walked by conservative advancement,
  // whose poses do not depend on the step (MotionChecker::Advance): the
  // planner's own check of each segment already left no sliver unchecked,
  // and a fine re-check would walk the same poses again, where only its
  // clock could differ. It did on as1's rod at a fine tessellation: the
  // straight pull out through the bores (118 depth searches of about 1 s)
  // was walked again, ran into the time limit, counted as blocked, and
  // the rod was NOT REMOVABLE.
  MotionChecker fine(problem, validity, fine_step, deadline);
  if (fine.WalksBySlack()) return report;
  fine.ProveByClearance();
  std::vector<Pose> certified;
  if (path->empty()) return report;
  certified.push_back(path->front());
  for (std::size_t i = 0; i + 1 < path->size(); ++i) {
    const Pose& a = (*path)[i];
    const Pose& b = (*path)[i + 1];
    if (fine.MotionValid(a, b)) {
      certified.push_back(b);
      continue;
    }
    // Re-plan this segment with edges checked at the fine step.
    PlanningProblem local = problem;
    local.start = a;
    local.goal = b;
    local.sampling_guide = {a, b};  // half the samples near the segment
    PlannerOptions local_options = options;
    local_options.seed = options.seed + 1000003ull * (i + 1);
    local_options.max_iterations = 50000;
    RrtConnectSettings settings;
    settings.randomize_parameters = true;
    const PlanResult repair = RunRrtConnect(local, fine, settings, local_options);
    if (!repair.solved()) {
      LogWarn("segment %zu of the path fails the fine re-check and could not be re-planned", i);
      report.certified = false;
      report.stopped_by_time_limit =
          repair.status == PlanStatus::kTimeLimit || std::chrono::steady_clock::now() >= deadline;
      return report;
    }
    certified.insert(certified.end(), repair.path.begin() + 1, repair.path.end());
    ++report.repaired_segments;
  }
  if (report.repaired_segments > 0) {
    LogInfo("certification re-planned %d path segment(s) that grazed S between checked poses",
            report.repaired_segments);
  }
  path->swap(certified);
  return report;
}

}  // namespace ausbau
