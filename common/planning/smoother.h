// Shortcut smoothing under the planner's own motion check: a shortcut is
// kept only when its motion is valid and it makes the path shorter, so the
// result is never less valid than the input.
#pragma once

#include <cstdint>
#include <vector>

#include "planning/state_space.h"

namespace ausbau {

struct SmoothOptions {
  std::uint64_t seed = 1;
  int attempts = 0;  // 0 = automatic: 100 + 10 per waypoint, at most 2000
  double time_limit_s = 10.0;
  double resolution = 0.01;  // as PlannerOptions::resolution
  void Check() const;
};

struct PathLength {
  double translation = 0;  // reference point travel, world units
  double rotation = 0;     // summed rotation angle, radians
  double normalized = 0;   // sum of d'_c with u = 0.5 (thesis metric)
};

PathLength MeasurePath(const PlanningProblem& problem, const std::vector<Pose>& path);

struct SmoothResult {
  std::vector<Pose> path;
  PathLength before, after;
  int shortcuts = 0;
  int attempts = 0;
};

SmoothResult SmoothPath(const PlanningProblem& problem, const PoseValidity& validity, const std::vector<Pose>& path,
                        const SmoothOptions& options);

}  // namespace ausbau
