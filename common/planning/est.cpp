#include <cmath>

#include "planning/single_tree_planners.h"
#include "planning/tree.h"

namespace ausbau {
namespace {

// Prefix sums over node weights with O(log n) update and weighted draw;
// capacity doubles as nodes are added (rebuilt in O(n), amortized O(1)).
class WeightIndex {
 public:
  void Append(double weight) {
    weights_.push_back(weight);
    if (weights_.size() > capacity_) {
      Rebuild(std::max<std::size_t>(64, 2 * capacity_));
    } else {
      Add(weights_.size() - 1, weight);
    }
  }
  void Set(std::size_t i, double weight) {
    Add(i, weight - weights_[i]);
    weights_[i] = weight;
  }
  // Smallest index whose prefix sum exceeds x * total.
  std::size_t Draw(double x) const {
    double target = x * Total();
    std::size_t position = 0;
    for (std::size_t step = highest_bit_; step > 0; step >>= 1) {
      const std::size_t next = position + step;
      if (next <= capacity_ && tree_[next] <= target) {
        position = next;
        target -= tree_[next];
      }
    }
    return std::min(position, weights_.size() - 1);
  }
  double Total() const {
    double sum = 0;
    for (std::size_t i = weights_.size(); i > 0; i -= i & (~i + 1)) sum += tree_[i];
    return sum;
  }

 private:
  void Add(std::size_t i, double delta) {
    for (std::size_t k = i + 1; k <= capacity_; k += k & (~k + 1)) tree_[k] += delta;
  }
  void Rebuild(std::size_t capacity) {
    capacity_ = capacity;
    highest_bit_ = 1;
    while (highest_bit_ * 2 <= capacity_) highest_bit_ *= 2;
    tree_.assign(capacity_ + 1, 0.0);
    for (std::size_t i = 0; i < weights_.size(); ++i) Add(i, weights_[i]);
  }

  std::vector<double> weights_;
  std::vector<double> tree_ = std::vector<double>(1, 0.0);
  std::size_t capacity_ = 0;
  std::size_t highest_bit_ = 0;
};

// A pose within range r1 of `center`: translation uniform in the ball of
// radius r1 * nu, rotation about a uniform axis by an angle uniform in
// [0, min(pi, 2 pi r1)] (d'_q = angle / (2 pi) <= r1); the problem's
// fixed rotation instead where it has one.
Pose SampleNear(const PlanningProblem& problem, const Pose& center, double r1, Random& random) {
  Eigen::Vector3d direction;
  do direction = {random.Uniform(-1, 1), random.Uniform(-1, 1), random.Uniform(-1, 1)};
  while (direction.squaredNorm() > 1.0 || direction.squaredNorm() < 1e-12);
  const double radius = r1 * problem.metric.nu * std::cbrt(random.Uniform01());
  Eigen::Vector3d axis;
  do axis = {random.Uniform(-1, 1), random.Uniform(-1, 1), random.Uniform(-1, 1)};
  while (axis.squaredNorm() > 1.0 || axis.squaredNorm() < 1e-12);
  const double angle = random.Uniform01() * std::min(M_PI, 2.0 * M_PI * r1);
  Pose out;
  out.t = center.t + radius * direction.normalized();
  out.q = (center.q * Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()))).normalized();
  if (problem.fixed_rotation) out.q = *problem.fixed_rotation;  // the same draws either way
  return out;
}

}  // namespace

EstSettings AutomaticEstSettings(const PlanningProblem& problem) {
  EstSettings settings;
  settings.r1 = std::clamp(0.25 * problem.robot_diagonal / problem.metric.nu, 1e-3, 0.05);
  settings.r2 = settings.r1;
  return settings;
}

PlanResult RunEst(const PlanningProblem& problem, const MotionChecker& motion, const EstSettings& given,
                  const PlannerOptions& options) {
  const EstSettings automatic = AutomaticEstSettings(problem);
  const double r1 = given.r1 > 0 ? given.r1 : automatic.r1;
  const double r2 = given.r2 > 0 ? given.r2 : automatic.r2;
  const StatsScope scope(motion.validity());
  const Budget budget(options, scope);
  Random random(options.seed);
  PoseTree tree(problem.metric);
  std::vector<int> neighbours;  // per node, itself included
  WeightIndex weights;
  auto add_node = [&](const Pose& pose, int parent) {
    const std::vector<int> near = tree.index.Within(pose, 0.5, r2);
    const int node = tree.Add(pose, parent);
    neighbours.push_back(1 + static_cast<int>(near.size()));
    weights.Append(1.0 / neighbours.back());
    for (int other : near) weights.Set(other, 1.0 / ++neighbours[other]);
    return node;
  };
  add_node(problem.start, -1);

  PlanResult result;
  if (!problem.goal && problem.InGoalRegion(problem.start)) {
    result.path = {problem.start};
    result.status = PlanStatus::kSolved;
  }
  std::int64_t iteration = 0;
  while (!result.solved() && budget.Continue(iteration, &result.status)) {
    ++iteration;
    int way;
    Pose candidate;
    if (problem.goal && random.Uniform01() < 0.05) {
      // Goal bias: the node nearest the goal steps towards it.
      way = tree.index.Nearest(*problem.goal, 0.5);
      const double range = problem.metric.Range(tree.poses[way], *problem.goal);
      candidate = range > r1 ? Interpolate(tree.poses[way], *problem.goal, r1 / range) : *problem.goal;
    } else {
      way = static_cast<int>(weights.Draw(random.Uniform01()));
      candidate = SampleNear(problem, tree.poses[way], r1, random);
    }
    if (!motion.MotionValid(tree.poses[way], candidate)) continue;
    const int added = add_node(candidate, way);
    if (GoalReached(problem, motion, tree, added, 2.0 * r1, &result.path)) result.status = PlanStatus::kSolved;
  }
  result.stats.iterations = iteration;
  result.stats.nodes = static_cast<std::int64_t>(tree.size());
  FillPartialPath(problem, tree, &result);
  scope.Fill(&result.stats);
  return result;
}

}  // namespace ausbau
