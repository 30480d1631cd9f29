#include "planning/rrt_connect.h"

#include <algorithm>

#include "core/log.h"
#include "planning/sampler.h"
#include "planning/tree.h"

namespace ausbau {
namespace {

enum class Extension { kTrapped, kAdvanced, kReached };

class RrtConnect {
 public:
  RrtConnect(const PlanningProblem& problem, const MotionChecker& motion, const RrtConnectSettings& settings,
             const PlannerOptions& options)
      : problem_(problem),
        motion_(motion),
        settings_(settings),
        options_(options),
        random_(options.seed),
        sampler_(problem, motion, ParseSamplerKind(options.sampler), options.sampler_sigma),
        start_tree_(problem.metric),
        goal_tree_(problem.metric) {}

  PlanResult Run() {
    const StatsScope scope(motion_.validity());
    const Budget budget(options_, scope);
    PlanResult result;
    start_tree_.Add(problem_.start, -1);
    if (problem_.goal) {
      goal_tree_.Add(*problem_.goal, -1);
    } else if (problem_.InGoalRegion(problem_.start)) {
      result.path = {problem_.start};
      result.status = PlanStatus::kSolved;
    }

    bool grow_start = true;
    std::int64_t iteration = 0;
    while (!result.solved() && budget.Continue(iteration, &result.status)) {
      ++iteration;
      if (!problem_.goal) MaybeAddGoalRoot();

      // Which tree grows: CR-RRTC the one with fewer nodes (alg. 5, line 3),
      // RRTC alternates (alg. 2).
      if (settings_.randomize_parameters) {
        grow_start = start_tree_.size() <= goal_tree_.size() || goal_tree_.size() == 0;
      } else {
        grow_start = goal_tree_.size() == 0 ? true : !grow_start;
      }
      PoseTree& current = grow_start ? start_tree_ : goal_tree_;
      PoseTree& other = grow_start ? goal_tree_ : start_tree_;

      const Pose target = sampler_.Sample(random_);
      int added = -1;
      if (Extend(current, target, &added) == Extension::kTrapped) continue;

      // A start-tree node in the disassembly region solves the problem.
      if (!problem_.goal && grow_start && problem_.InGoalRegion(current.poses[added])) {
        result.path = start_tree_.PathFromRoot(added);
        result.status = PlanStatus::kSolved;
        break;
      }
      if (other.size() == 0) continue;
      // Try to connect the other tree to the new node (alg. 5, lines 10-16).
      int other_added = -1;
      if (Extend(other, current.poses[added], &other_added) != Extension::kReached) continue;
      const int start_node = grow_start ? added : other_added;
      const int goal_node = grow_start ? other_added : added;
      result.path = start_tree_.PathFromRoot(start_node);
      std::vector<Pose> tail = goal_tree_.BranchToRoot(goal_node);
      // The connecting node exists in both trees: keep it once.
      result.path.insert(result.path.end(), tail.begin() + 1, tail.end());
      result.status = PlanStatus::kSolved;
    }
    LogDebug("start tree %zu nodes, goal tree %zu nodes (%lld goal roots)", start_tree_.size(), goal_tree_.size(),
             static_cast<long long>(goal_roots_));
    result.stats.iterations = iteration;
    result.stats.nodes = static_cast<std::int64_t>(start_tree_.size() + goal_tree_.size());
    FillPartialPath(problem_, start_tree_, &result);
    scope.Fill(&result.stats);
    return result;
  }

 private:
  // Grows `tree` from its nearest node towards `target` by at most
  // range_max (eq. 3), keeping the valid part of the edge (getValidEdge).
  Extension Extend(PoseTree& tree, const Pose& target, int* added) {
    const double u = settings_.randomize_parameters ? random_.UniformOpen01() : settings_.u;
    const double range_max = settings_.randomize_parameters ? random_.UniformOpen01() : settings_.range_max;
    const int near = tree.index.Nearest(target, u);
    const Pose& from = tree.poses[near];
    const double range = problem_.metric.Range(from, target);
    const bool clipped = range > range_max;
    const Pose to = clipped ? Interpolate(from, target, range_max / range) : target;
    if (!settings_.partial_extension) {
      if (!motion_.MotionValid(from, to)) return Extension::kTrapped;
      *added = tree.Add(to, near);
      return clipped ? Extension::kAdvanced : Extension::kReached;
    }
    Pose reached;
    const double fraction = motion_.ValidPrefix(from, to, &reached);
    if (fraction <= 0.0) return Extension::kTrapped;
    *added = tree.Add(reached, near);
    return (fraction >= 1.0 && !clipped) ? Extension::kReached : Extension::kAdvanced;
  }

  // Disassembly problems have a goal region instead of a goal pose: the
  // goal tree is rooted at poses sampled in the region, one more whenever
  // the roots are fewer than half the goal tree's nodes (as OMPL does for
  // sampleable goal regions). D's AABB is separated from S's there, so the
  // roots are collision-free by construction; they must lie in bounds.
  void MaybeAddGoalRoot() {
    if (goal_tree_.size() > 0 && goal_roots_ * 2 >= static_cast<std::int64_t>(goal_tree_.size())) return;
    Pose pose;
    if (SampleGoalRegion(problem_, random_, &pose)) {
      goal_tree_.Add(pose, -1);
      ++goal_roots_;
    }
  }

  const PlanningProblem& problem_;
  const MotionChecker& motion_;
  const RrtConnectSettings settings_;
  const PlannerOptions& options_;
  Random random_;
  Sampler sampler_;
  PoseTree start_tree_;
  PoseTree goal_tree_;
  std::int64_t goal_roots_ = 0;
};

}  // namespace

PlanResult RunRrtConnect(const PlanningProblem& problem, const MotionChecker& motion,
                         const RrtConnectSettings& settings, const PlannerOptions& options) {
  return RrtConnect(problem, motion, settings, options).Run();
}

}  // namespace ausbau
