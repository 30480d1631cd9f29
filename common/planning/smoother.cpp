#include "planning/smoother.h"

#include <chrono>
#include <cmath>

#include "core/error.h"
#include "core/random.h"

namespace ausbau {

void SmoothOptions::Check() const {
  if (attempts < 0) throw InputError("--attempts: must be >= 0");
  if (!(time_limit_s > 0) || !std::isfinite(time_limit_s)) throw InputError("--time-limit: must be positive");
  if (!(resolution > 0 && resolution <= 0.1)) throw InputError("--resolution: must lie in (0, 0.1]");
}

PathLength MeasurePath(const PlanningProblem& problem, const std::vector<Pose>& path) {
  PathLength length;
  for (std::size_t i = 1; i < path.size(); ++i) {
    length.translation += (path[i].t - path[i - 1].t).norm();
    length.rotation += RotationAngle(path[i - 1].q, path[i].q);
    length.normalized += problem.metric.Distance(path[i - 1], path[i], 0.5);
  }
  return length;
}

namespace {

double SegmentCost(const PlanningProblem& problem, const std::vector<Pose>& path, std::size_t from, std::size_t to) {
  double cost = 0;
  for (std::size_t i = from; i < to; ++i) cost += problem.metric.Distance(path[i], path[i + 1], 0.5);
  return cost;
}

}  // namespace

SmoothResult SmoothPath(const PlanningProblem& problem, const PoseValidity& validity, const std::vector<Pose>& input,
                        const SmoothOptions& options) {
  options.Check();
  // Shortcuts are few: check them at the certification step (planner step / 4,
  // planning/certify.h) so that smoothing never trades certainty for length.
  const MotionChecker motion(problem, validity, options.resolution * problem.robot_diagonal / 4.0);
  SmoothResult result;
  result.path = input;
  result.before = MeasurePath(problem, input);
  Random random(options.seed);
  const int attempts =
      options.attempts > 0 ? options.attempts : std::min<int>(2000, 100 + 10 * static_cast<int>(input.size()));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.time_limit_s);

  std::vector<Pose>& path = result.path;
  for (int attempt = 0; attempt < attempts && path.size() >= 3; ++attempt) {
    if (std::chrono::steady_clock::now() >= deadline) break;
    ++result.attempts;
    // Two random points on two different segments i < j; the path between
    // them is replaced by the straight motion a -> b when that is valid and
    // shorter.
    const std::size_t segments = path.size() - 1;
    std::size_t i = random.Index(segments), j = random.Index(segments);
    const double fa = random.Uniform01(), fb = random.Uniform01();
    if (i == j) continue;
    if (i > j) std::swap(i, j);
    const Pose a = fa == 0.0 ? path[i] : Interpolate(path[i], path[i + 1], fa);
    const Pose b = Interpolate(path[j], path[j + 1], fb);
    const double old_cost = problem.metric.Distance(a, path[i + 1], 0.5) + SegmentCost(problem, path, i + 1, j) +
                            problem.metric.Distance(path[j], b, 0.5);
    const double new_cost = problem.metric.Distance(a, b, 0.5);
    if (!(new_cost < old_cost - 1e-12)) continue;
    if (!motion.IsValid(a) || !motion.MotionValid(a, b)) continue;
    std::vector<Pose> next(path.begin(), path.begin() + i + 1);
    if (fa != 0.0) next.push_back(a);
    next.push_back(b);
    next.insert(next.end(), path.begin() + j + 1, path.end());
    path.swap(next);
    ++result.shortcuts;
  }
  // Drop waypoints whose neighbours see each other directly.
  for (std::size_t i = 0; i + 2 < path.size();) {
    if (motion.MotionValid(path[i], path[i + 2])) {
      path.erase(path.begin() + i + 1);
    } else {
      ++i;
    }
  }
  result.after = MeasurePath(problem, path);
  return result;
}

}  // namespace ausbau
