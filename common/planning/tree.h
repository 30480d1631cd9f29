// A tree of poses with a nearest-neighbour index, shared by the tree
// planners (RRT, RRT-Connect, EST).
#pragma once

#include <algorithm>
#include <chrono>
#include <vector>

#include "core/cancel.h"
#include "planning/nearest_neighbors.h"
#include "planning/planner.h"

namespace ausbau {

struct PoseTree {
  explicit PoseTree(const Metric& metric) : index(metric) {}
  std::vector<Pose> poses;
  std::vector<int> parents;  // -1 for a root
  NearestNeighbors index;

  int Add(const Pose& pose, int parent) {
    poses.push_back(pose);
    parents.push_back(parent);
    index.Add(pose);
    return static_cast<int>(poses.size()) - 1;
  }
  std::size_t size() const { return poses.size(); }
  // Poses from `node` up to its root.
  std::vector<Pose> BranchToRoot(int node) const {
    std::vector<Pose> branch;
    for (int i = node; i >= 0; i = parents[i]) branch.push_back(poses[i]);
    return branch;
  }
  // Poses from the root down to `node`.
  std::vector<Pose> PathFromRoot(int node) const {
    std::vector<Pose> path = BranchToRoot(node);
    std::reverse(path.begin(), path.end());
    return path;
  }
};

// An unsolved run's best partial path: from the root to the node of `tree`
// with the most PartialProgress (the first of equals).
inline void FillPartialPath(const PlanningProblem& problem, const PoseTree& tree, PlanResult* result) {
  if (result->solved() || tree.size() == 0) return;
  int best = 0;
  double best_progress = PartialProgress(problem, tree.poses[0]);
  for (std::size_t i = 1; i < tree.size(); ++i) {
    const double progress = PartialProgress(problem, tree.poses[i]);
    if (progress > best_progress) {
      best_progress = progress;
      best = static_cast<int>(i);
    }
  }
  result->partial = tree.PathFromRoot(best);
  result->partial_progress = best_progress;
}

// The single-tree planners' goalReached (thesis alg. 1, line 9) for the
// node just added: in the disassembly region, or, with a goal pose, within
// `connect_range` (eq. 3) of it with a valid straight motion to it. On
// success fills the path from the root (ending at the goal pose).
inline bool GoalReached(const PlanningProblem& problem, const MotionChecker& motion, const PoseTree& tree, int node,
                        double connect_range, std::vector<Pose>* path) {
  const Pose& pose = tree.poses[node];
  if (!problem.goal) {
    if (!problem.InGoalRegion(pose)) return false;
    *path = tree.PathFromRoot(node);
    return true;
  }
  const double range = problem.metric.Range(pose, *problem.goal);
  if (range > connect_range || !motion.MotionValid(pose, *problem.goal)) return false;
  *path = tree.PathFromRoot(node);
  if (range > 0) path->push_back(*problem.goal);
  return true;
}

// Collects the run's statistics from the validity counters and the clock.
class StatsScope {
 public:
  explicit StatsScope(const PoseValidity& validity)
      : validity_(validity),
        checks_(validity.checks()),
        invalid_(validity.invalid_checks()),
        begin_(std::chrono::steady_clock::now()) {}
  void Fill(PlanStats* stats) const {
    stats->collision_checks = validity_.checks() - checks_;
    stats->invalid_checks = validity_.invalid_checks() - invalid_;
    stats->time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin_).count();
  }
  std::chrono::steady_clock::time_point begin() const { return begin_; }
  std::int64_t checks() const { return validity_.checks() - checks_; }  // so far

 private:
  const PoseValidity& validity_;
  std::int64_t checks_, invalid_;
  std::chrono::steady_clock::time_point begin_;
};

// The planner loop's stop rule: the work budgets first (iterations, checks:
// deterministic), then a cancellation (PlannerOptions::cancel, or the
// process-wide one of core/cancel.h), then the wall clock (the safety net:
// kTimeLimit, a run cut short). It also reports progress
// (PlannerOptions::progress), which never changes whether it continues.
class Budget {
 public:
  Budget(const PlannerOptions& options, const StatsScope& scope)
      : max_iterations_(options.max_iterations),
        max_checks_(options.max_checks),
        scope_(scope),
        cancel_(options.cancel),
        progress_(options.progress),
        deadline_(scope.begin() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                      std::chrono::duration<double>(options.time_limit_s))),
        next_report_(scope.begin()) {}
  // Returns false and sets *status when the budget is spent.
  bool Continue(std::int64_t iteration, PlanStatus* status) const {
    if ((max_iterations_ > 0 && iteration >= max_iterations_) || (max_checks_ > 0 && scope_.checks() >= max_checks_)) {
      *status = PlanStatus::kIterationLimit;
      return false;
    }
    if ((cancel_ != nullptr && cancel_->load(std::memory_order_relaxed)) || CancelRequested()) {
      *status = PlanStatus::kCancelled;
      return false;
    }
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline_) {
      *status = PlanStatus::kTimeLimit;
      return false;
    }
    if (progress_ && now >= next_report_) {
      next_report_ = now + std::chrono::milliseconds(200);
      progress_(iteration, max_iterations_);
    }
    return true;
  }

 private:
  std::int64_t max_iterations_, max_checks_;
  const StatsScope& scope_;
  const std::atomic<bool>* cancel_;
  const ProgressCallback& progress_;
  std::chrono::steady_clock::time_point deadline_;
  mutable std::chrono::steady_clock::time_point next_report_;
};

}  // namespace ausbau
