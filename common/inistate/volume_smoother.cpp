#include "inistate/volume_smoother.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/random.h"

namespace ausbau {
namespace {

// The largest volume on the straight motion a -> b (b included, a not),
// stopping early (returning a value above `limit`) once it exceeds limit or
// leaves the bounds.
double SegmentMax(const PlanningProblem& problem, IntersectionVolume& volume, VolumeMeasure measure, const Pose& a,
                  const Pose& b, double step, double limit = std::numeric_limits<double>::infinity()) {
  const int steps = std::max(1, static_cast<int>(std::ceil(MaxDisplacement(a, b, problem.robot_radius) / step)));
  double worst = 0;
  for (int k = 1; k <= steps; ++k) {
    const Pose pose = Interpolate(a, b, static_cast<double>(k) / steps);
    if (!problem.InBounds(pose)) return std::numeric_limits<double>::infinity();
    worst = std::max(worst, volume.Measure(measure, pose, limit));
    if (worst > limit) return worst;
  }
  return worst;
}

}  // namespace

double MaxVolumeAlong(const PlanningProblem& problem, IntersectionVolume& volume, VolumeMeasure measure,
                      const std::vector<Pose>& path, double step) {
  if (path.empty()) return 0;
  double worst = volume.Measure(measure, path.front());
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    worst = std::max(worst, SegmentMax(problem, volume, measure, path[i], path[i + 1], step));
  }
  return worst;
}

VolumeSmoothResult SmoothUnderVolume(const PlanningProblem& problem, IntersectionVolume& volume, VolumeMeasure measure,
                                     const std::vector<Pose>& input, const SmoothOptions& options) {
  options.Check();
  const double step = options.resolution * problem.robot_diagonal / 4.0;
  VolumeSmoothResult result;
  result.path = input;
  std::vector<Pose>& path = result.path;
  // segment_max[k]: the largest volume on segment k -> k + 1 (its end pose
  // included), kept in step with the path.
  std::vector<double> segment_max;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    segment_max.push_back(SegmentMax(problem, volume, measure, path[i], path[i + 1], step));
  }
  const double start_volume = path.empty() ? 0.0 : volume.Measure(measure, path.front());
  result.max_before = start_volume;
  for (double m : segment_max) result.max_before = std::max(result.max_before, m);

  Random random(options.seed);
  const int attempts =
      options.attempts > 0 ? options.attempts : std::min<int>(2000, 100 + 10 * static_cast<int>(input.size()));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.time_limit_s);
  for (int attempt = 0; attempt < attempts && path.size() >= 3; ++attempt) {
    if (std::chrono::steady_clock::now() >= deadline) break;
    ++result.attempts;
    std::size_t i = random.Index(path.size()), j = random.Index(path.size());
    if (i > j) std::swap(i, j);
    if (j < i + 2) continue;
    double old_cost = 0, section_max = 0;
    for (std::size_t k = i; k < j; ++k) {
      old_cost += problem.metric.Distance(path[k], path[k + 1], 0.5);
      section_max = std::max(section_max, segment_max[k]);
    }
    if (!(problem.metric.Distance(path[i], path[j], 0.5) < old_cost - 1e-12)) continue;
    const double shortcut_max = SegmentMax(problem, volume, measure, path[i], path[j], step, section_max);
    if (shortcut_max > section_max) continue;
    path.erase(path.begin() + i + 1, path.begin() + j);
    segment_max.erase(segment_max.begin() + i + 1, segment_max.begin() + j);
    segment_max[i] = shortcut_max;
    ++result.shortcuts;
  }
  result.max_after = start_volume;
  for (double m : segment_max) result.max_after = std::max(result.max_after, m);
  return result;
}

}  // namespace ausbau
