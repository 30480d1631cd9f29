#include "inistate/volume_smoother.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ausbau {
namespace {

// The largest volume on the straight motion a -> b (b included, a not),
// stopping early (returning a value above `limit`) once it exceeds limit or
// leaves the bounds. The poses are the motion checker's (MotionChecker:
// equal sub-steps of at most `step` vertex motion).
double SegmentMax(const PlanningProblem& problem, IntersectionVolume& volume, VolumeMeasure measure, const Pose& a,
                  const Pose& b, double step, double limit) {
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
                      const std::vector<Pose>& path, double step, double limit) {
  if (path.empty()) return 0;
  double worst = volume.Measure(measure, path.front(), limit);
  for (std::size_t i = 0; i + 1 < path.size() && !(worst > limit); ++i) {
    worst = std::max(worst, SegmentMax(problem, volume, measure, path[i], path[i + 1], step, limit));
  }
  return worst;
}

bool VolumeGuard::Accepts(const std::vector<Pose>& replaced, const std::vector<Pose>& replacement) const {
  const double removed = MaxVolumeAlong(*problem_, *volume_, measure_, replaced, step_);
  // A replaced section that is itself refused somewhere (a rigid solid into
  // S, or out of the bounds: infinite) justifies no replacement.
  if (!std::isfinite(removed)) return false;
  return MaxVolumeAlong(*problem_, *volume_, measure_, replacement, step_, removed) <= removed;
}

VolumeSmoothResult SmoothUnderVolume(const PlanningProblem& problem, IntersectionVolume& volume, VolumeMeasure measure,
                                     const std::vector<Pose>& input, const SmoothOptions& options) {
  options.Check();
  const double step = options.resolution * problem.robot_diagonal / 4.0;
  VolumeSmoothResult result;
  result.max_before = MaxVolumeAlong(problem, volume, measure, input, step);
  if (input.size() < 3) {
    result.path = input;
    result.max_after = result.max_before;
    return result;
  }
  // sigma_1's end is c_inter, where sigma_2 starts: held, as a goal pose
  // holds the end of a rigid path (no retreat, no freeze of the tail).
  PlanningProblem held_end = problem;
  held_end.goal = input.back();
  // The motions are checked against the input's largest volume (no change
  // may exceed it anyway); the guard then compares with what they replace.
  const VolumeValidity validity(volume, measure, result.max_before);
  const VolumeGuard guard(held_end, volume, measure, step);
  const SmoothResult smoothed = SmoothPath(held_end, validity, input, options, &guard);
  result.path = smoothed.path;
  result.shortcuts = smoothed.shortcuts;
  result.partial_shortcuts = smoothed.partial_shortcuts;
  result.attempts = smoothed.attempts;
  result.max_after = MaxVolumeAlong(problem, volume, measure, result.path, step);
  return result;
}

}  // namespace ausbau
