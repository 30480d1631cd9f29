#include "planning/rrt_connect.h"

#include <algorithm>
#include <chrono>

#include "core/log.h"
#include "planning/nearest_neighbors.h"

namespace ausbau {
namespace {

struct Tree {
  explicit Tree(const Metric& metric) : index(metric) {}
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
};

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
        start_tree_(problem.metric),
        goal_tree_(problem.metric) {}

  PlanResult Run() {
    const auto begin = std::chrono::steady_clock::now();
    const std::int64_t checks_before = motion_.validity().checks();
    const std::int64_t invalid_before = motion_.validity().invalid_checks();
    PlanResult result;
    start_tree_.Add(problem_.start, -1);
    if (problem_.goal) {
      goal_tree_.Add(*problem_.goal, -1);
    } else if (problem_.InGoalRegion(problem_.start)) {
      result.path = {problem_.start};
      result.status = PlanStatus::kSolved;
    }

    const auto deadline = begin + std::chrono::duration<double>(options_.time_limit_s);
    bool grow_start = true;
    std::int64_t iteration = 0;
    while (!result.solved()) {
      if (options_.max_iterations > 0 && iteration >= options_.max_iterations) {
        result.status = PlanStatus::kIterationLimit;
        break;
      }
      if (std::chrono::steady_clock::now() >= deadline) {
        result.status = PlanStatus::kTimeLimit;
        break;
      }
      ++iteration;
      if (!problem_.goal) MaybeAddGoalRoot();

      // Which tree grows: CR-RRTC the one with fewer nodes (alg. 5, line 3),
      // RRTC alternates (alg. 2).
      if (settings_.randomize_parameters) {
        grow_start = start_tree_.size() <= goal_tree_.size() || goal_tree_.size() == 0;
      } else {
        grow_start = goal_tree_.size() == 0 ? true : !grow_start;
      }
      Tree& current = grow_start ? start_tree_ : goal_tree_;
      Tree& other = grow_start ? goal_tree_ : start_tree_;

      const Pose target = problem_.SampleUniform(random_);
      int added = -1;
      if (Extend(current, target, &added) == Extension::kTrapped) continue;

      // A start-tree node in the disassembly region solves the problem.
      if (!problem_.goal && grow_start && problem_.InGoalRegion(current.poses[added])) {
        result.path = start_tree_.BranchToRoot(added);
        std::reverse(result.path.begin(), result.path.end());
        result.status = PlanStatus::kSolved;
        break;
      }
      if (other.size() == 0) continue;
      // Try to connect the other tree to the new node (alg. 5, lines 10-16).
      int other_added = -1;
      if (Extend(other, current.poses[added], &other_added) != Extension::kReached) continue;
      const int start_node = grow_start ? added : other_added;
      const int goal_node = grow_start ? other_added : added;
      result.path = start_tree_.BranchToRoot(start_node);
      std::reverse(result.path.begin(), result.path.end());
      std::vector<Pose> tail = goal_tree_.BranchToRoot(goal_node);
      // The connecting node exists in both trees: keep it once.
      result.path.insert(result.path.end(), tail.begin() + 1, tail.end());
      result.status = PlanStatus::kSolved;
    }
    LogDebug("start tree %zu nodes, goal tree %zu nodes (%lld goal roots)", start_tree_.size(), goal_tree_.size(),
             static_cast<long long>(goal_roots_));
    result.stats.iterations = iteration;
    result.stats.nodes = static_cast<std::int64_t>(start_tree_.size() + goal_tree_.size());
    result.stats.collision_checks = motion_.validity().checks() - checks_before;
    result.stats.invalid_checks = motion_.validity().invalid_checks() - invalid_before;
    result.stats.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    return result;
  }

 private:
  // Grows `tree` from its nearest node towards `target` by at most
  // range_max (eq. 3), keeping the valid part of the edge (getValidEdge).
  Extension Extend(Tree& tree, const Pose& target, int* added) {
    const double u = settings_.randomize_parameters ? random_.UniformOpen01() : settings_.u;
    const double range_max = settings_.randomize_parameters ? random_.UniformOpen01() : settings_.range_max;
    const int near = tree.index.Nearest(target, u);
    const Pose& from = tree.poses[near];
    const double range = problem_.metric.Range(from, target);
    const bool clipped = range > range_max;
    const Pose to = clipped ? Interpolate(from, target, range_max / range) : target;
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
    for (int attempt = 0; attempt < 100; ++attempt) {
      const Pose pose = problem_.SampleUniform(random_);
      if (problem_.InGoalRegion(pose) && problem_.InBounds(pose)) {
        goal_tree_.Add(pose, -1);
        ++goal_roots_;
        return;
      }
    }
  }

  const PlanningProblem& problem_;
  const MotionChecker& motion_;
  const RrtConnectSettings settings_;
  const PlannerOptions& options_;
  Random random_;
  Tree start_tree_;
  Tree goal_tree_;
  std::int64_t goal_roots_ = 0;
};

}  // namespace

PlanResult RunRrtConnect(const PlanningProblem& problem, const MotionChecker& motion,
                         const RrtConnectSettings& settings, const PlannerOptions& options) {
  return RrtConnect(problem, motion, settings, options).Run();
}

}  // namespace ausbau
