#include "planning/sampler.h"
#include "planning/single_tree_planners.h"
#include "planning/tree.h"

namespace ausbau {

PlanResult RunRrt(const PlanningProblem& problem, const MotionChecker& motion, const PlannerOptions& options) {
  const StatsScope scope(motion.validity());
  const Budget budget(options, scope);
  Random random(options.seed);
  Sampler sampler(problem, motion, ParseSamplerKind(options.sampler), options.sampler_sigma);
  PoseTree tree(problem.metric);
  tree.Add(problem.start, -1);
  PlanResult result;
  if (!problem.goal && problem.InGoalRegion(problem.start)) {
    result.path = {problem.start};
    result.status = PlanStatus::kSolved;
  }
  std::int64_t iteration = 0;
  while (!result.solved() && budget.Continue(iteration, &result.status)) {
    ++iteration;
    const bool toward_goal = problem.goal && random.Uniform01() < 0.05;
    const Pose target = toward_goal ? *problem.goal : sampler.Sample(random);
    const int near = tree.index.Nearest(target, options.u);
    const Pose& from = tree.poses[near];
    const double range = problem.metric.Range(from, target);
    const Pose to = range > options.range_max ? Interpolate(from, target, options.range_max / range) : target;
    Pose reached;
    if (motion.ValidPrefix(from, to, &reached) <= 0.0) continue;
    const int added = tree.Add(reached, near);
    if (GoalReached(problem, motion, tree, added, options.range_max, &result.path)) result.status = PlanStatus::kSolved;
  }
  result.stats.iterations = iteration;
  result.stats.nodes = static_cast<std::int64_t>(tree.size());
  FillPartialPath(problem, tree, &result);
  scope.Fill(&result.stats);
  return result;
}

}  // namespace ausbau
