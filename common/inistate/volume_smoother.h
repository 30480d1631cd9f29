// Shortcut smoothing of sigma_1 (the InIState part of a path) under its
// intersection volume. A shortcut from waypoint i to waypoint j replaces the
// section between them only when it is shorter (normalized metric, u = 1/2)
// and the largest volume along it, checked densely, is at most the largest
// along the section it replaces. So neither the path's maximum nor any
// section's maximum ever rises: smoothing cannot trade a short path for a
// deeper intersection somewhere (a plain "max <= path maximum" test would
// let a shortcut push a rigid rail into its lip as long as a clip elsewhere
// intersects more). Start and end stay.
#pragma once

#include <vector>

#include "inistate/intersection_volume.h"
#include "planning/smoother.h"

namespace ausbau {

struct VolumeSmoothResult {
  std::vector<Pose> path;                // planning convention
  double max_before = 0, max_after = 0;  // largest volume along the path, densely
  int shortcuts = 0, attempts = 0;
};

// Poses along the path are checked so that no vertex of D moves more than
// options.resolution x D's diagonal / 4 between two of them (the smoother's
// and the certification's step). `volume` is used with its own buffers (not
// thread-safe; pass a clone).
VolumeSmoothResult SmoothUnderVolume(const PlanningProblem& problem, IntersectionVolume& volume, VolumeMeasure measure,
                                     const std::vector<Pose>& path, const SmoothOptions& options);

// The largest volume along a path, densely at `step` (world units of vertex
// motion between checked poses).
double MaxVolumeAlong(const PlanningProblem& problem, IntersectionVolume& volume, VolumeMeasure measure,
                      const std::vector<Pose>& path, double step);

}  // namespace ausbau
