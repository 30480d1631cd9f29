#include "planning/rrt_connect.h"

#include <algorithm>

#include "core/log.h"
#include "planning/passage_direction.h"
#include "planning/sampler.h"
#include "planning/smoother.h"
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
    if (!problem_.goal && settings_.exit_axes > 0) {
      local_normal_axes_ = SurfaceNormalAxes(problem_.robot, Eigen::Quaterniond::Identity());
      if (static_cast<int>(local_normal_axes_.size()) > settings_.exit_axes)
        local_normal_axes_.resize(settings_.exit_axes);
    }
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
    // The start's branches (straight pulls' stops, walked valid): the tree
    // grows from them as from any node.
    for (const Pose& branch : options_.start_branches) {
      if (result.solved()) break;
      const int added = start_tree_.Add(branch, 0);
      if (!problem_.goal && problem_.InGoalRegion(branch)) {
        result.path = start_tree_.PathFromRoot(added);
        result.status = PlanStatus::kSolved;
      }
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
      if (!problem_.goal && grow_start && ExitFrom(added, &result.path)) {
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
    LogDebug(
        "start tree %zu nodes, goal tree %zu nodes (%lld goal roots); second tries along a passage: %lld, "
        "%lld of them added a node",
        start_tree_.size(), goal_tree_.size(), static_cast<long long>(goal_roots_),
        static_cast<long long>(second_tries_), static_cast<long long>(second_tries_added_));
    LogDebug("exit moves from new nodes: %lld pulls, %lld quarter turns", static_cast<long long>(exit_pulls_),
             static_cast<long long>(exit_turns_));
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
    Pose reached;
    const double fraction = EdgeFraction(from, to, &reached);
    // How often this tree's extensions were trapped lately (a moving
    // average over about kTrappedWindow extensions).
    double& trapped_share = &tree == &start_tree_ ? start_trapped_share_ : goal_trapped_share_;
    trapped_share += ((fraction > 0.0 ? 0.0 : 1.0) - trapped_share) / kTrappedWindow;
    if (fraction > 0.0) {
      *added = tree.Add(reached, near);
      return (fraction >= 1.0 && !clipped) ? Extension::kReached : Extension::kAdvanced;
    }
    // The second try only for a tree that is nearly always trapped: where
    // extensions mostly get somewhere, it would only add checks.
    Pose shaped;
    if (trapped_share <= kSecondTryShare || !ShapedByPassage(tree, near, to, &shaped)) return Extension::kTrapped;
    ++second_tries_;
    if (EdgeFraction(from, shaped, &reached) <= 0.0) return Extension::kTrapped;
    ++second_tries_added_;
    *added = tree.Add(reached, near);
    return Extension::kAdvanced;
  }

  // Disassembly: from start-tree node `node`, straight pulls out of S's box
  // along D's first exit_axes surface-normal axes (both ways), as
  // TryStraightPulls does from the start, then quarter turns about the same
  // axes (both ways), each followed by the pulls. The lift out of a slot or
  // an opening and the quarter turn of a key, a bayonet or a clip come
  // last, and a sampled pose rarely lines up with them; most such moves are
  // blocked after a check or two. The valid part of a turn joins the tree:
  // partly turned nodes grow on towards the turn (panel-keyhole seeds 1-3,
  // 7 runs: 6 solved within 60 s, 5 where only turns a pull gets out from
  // join, which spares the other families turned nodes they do not need:
  // panel-channel median 1.6 s against 2.9 s). On success *path runs from
  // the root to the node (and its turn) and out.
  bool ExitFrom(int node, std::vector<Pose>* path) {
    const Pose from = start_tree_.poses[node];
    if (const std::optional<Pose> out = PullOut(from)) {
      *path = start_tree_.PathFromRoot(node);
      path->push_back(*out);
      return true;
    }
    if (problem_.fixed_rotation) return false;  // translation-only planning does not turn D
    for (const Eigen::Vector3d& local : local_normal_axes_) {
      for (const double sign : {1.0, -1.0}) {
        Pose quarter = from;
        quarter.q = (Eigen::Quaterniond(Eigen::AngleAxisd(sign * M_PI / 2, from.q * local)) * from.q).normalized();
        ++exit_turns_;
        Pose turned;
        if (motion_.ValidPrefix(from, quarter, &turned) <= 0.0) continue;
        const int added = start_tree_.Add(turned, node);
        const std::optional<Pose> out = PullOut(turned);
        if (!out) continue;
        *path = start_tree_.PathFromRoot(added);
        path->push_back(*out);
        return true;
      }
    }
    return false;
  }

  // The end of the first free straight pull out of S's box from `from`
  // along ExitFrom's axes, both ways; none when every one is blocked.
  std::optional<Pose> PullOut(const Pose& from) {
    for (const Eigen::Vector3d& local : local_normal_axes_) {
      for (const double sign : {1.0, -1.0}) {
        const std::optional<Pose> end = StraightExitPose(problem_, from, sign * (from.q * local));
        if (!end) continue;
        ++exit_pulls_;
        Pose reached;
        if (motion_.ValidPrefix(from, *end, &reached) >= 1.0) return end;
      }
    }
    return std::nullopt;
  }

  // An edge walked as the settings say: the fraction of its valid prefix and
  // its end in *reached (partial extension), or all (1) or nothing (0).
  double EdgeFraction(const Pose& from, const Pose& to, Pose* reached) const {
    if (settings_.partial_extension) return motion_.ValidPrefix(from, to, reached);
    if (!motion_.MotionValid(from, to)) return 0.0;
    *reached = to;
    return 1.0;
  }

  // The second try of a trapped extension (passage_direction.h): `to` shaped
  // by the spread of the tree's nodes nearest to node `near`.
  bool ShapedByPassage(const PoseTree& tree, int near, const Pose& to, Pose* shaped) const {
    if (settings_.passage_neighbors <= 0 || static_cast<int>(tree.size()) < kPassageMinNeighbors) return false;
    const Pose& from = tree.poses[near];
    neighbors_.clear();
    for (const int index : tree.index.KNearest(from, 0.5, settings_.passage_neighbors)) {
      neighbors_.push_back(tree.poses[index]);
    }
    return ShapeAlongPassage(problem_.metric, from, to, neighbors_, shaped);
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
  mutable std::vector<Pose> neighbors_;  // ShapedByPassage's scratch
  // The second try is spent only while more than kSecondTryShare of about
  // the last kTrappedWindow extensions of the tree were trapped. Chosen from
  // 0.5, 0.8 and 0.95 (docs/benchmarks.md): flange-1.0, seeds 1-4 within
  // 120 s, solved 4, 4 and 3; alpha-1.5, seeds 1-3, thousands of checks
  // 60/54/18, 22/35/27 and 21/51/28 (the last the same as without it).
  static constexpr double kTrappedWindow = 64;
  static constexpr double kSecondTryShare = 0.8;
  std::int64_t second_tries_ = 0, second_tries_added_ = 0;
  double start_trapped_share_ = 0, goal_trapped_share_ = 0;
  std::vector<Eigen::Vector3d> local_normal_axes_;  // ExitFrom's axes, in D's frame
  std::int64_t exit_pulls_ = 0, exit_turns_ = 0;
};

}  // namespace

PlanResult RunRrtConnect(const PlanningProblem& problem, const MotionChecker& motion,
                         const RrtConnectSettings& settings, const PlannerOptions& options) {
  return RrtConnect(problem, motion, settings, options).Run();
}

}  // namespace ausbau
