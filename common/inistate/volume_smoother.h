// Smoothing of sigma_1 (the InIState part of a path) under its intersection
// volume: the rigid smoother (planning/smoother.h: full and partial
// shortcuts, dropped waypoints) with sigma_1's end held (c_inter, where
// sigma_2 starts) and a VolumeGuard. A change replacing a section of the
// path is kept only when it is shorter (normalized metric, u = 1/2) and the
// largest volume along it, checked densely, is at most the largest along the
// section it replaces (its first pose included: both start there). So
// neither the path's maximum nor any section's maximum ever rises:
// smoothing cannot trade a short path for a deeper intersection somewhere
// (a plain "max <= path maximum" test would let a shortcut push a rigid rail
// into its lip as long as a clip elsewhere intersects more). Start and end
// stay.
#pragma once

#include <limits>
#include <vector>

#include "inistate/intersection_volume.h"
#include "planning/replacement_guard.h"
#include "planning/smoother.h"

namespace ausbau {

// The guard: a replacement's largest volume (densely, at `step` of vertex
// motion) at most the replaced section's. `volume` is used with its own
// buffers (not thread-safe; pass a clone) and must outlive the guard.
class VolumeGuard : public ReplacementGuard {
 public:
  VolumeGuard(const PlanningProblem& problem, IntersectionVolume& volume, VolumeMeasure measure, double step)
      : problem_(&problem), volume_(&volume), measure_(measure), step_(step) {}
  bool Accepts(const std::vector<Pose>& replaced, const std::vector<Pose>& replacement) const override;

 private:
  const PlanningProblem* problem_;
  IntersectionVolume* volume_;
  VolumeMeasure measure_;
  double step_;
};

struct VolumeSmoothResult {
  std::vector<Pose> path;                // planning convention
  double max_before = 0, max_after = 0;  // largest volume along the path, densely
  int shortcuts = 0, attempts = 0;       // shortcuts: full and partial ones kept
  int partial_shortcuts = 0;
};

// Poses along the path are checked so that no vertex of D moves more than
// options.resolution x D's diagonal / 4 between two of them (the smoother's
// and the certification's step). `volume` is used with its own buffers (not
// thread-safe; pass a clone).
VolumeSmoothResult SmoothUnderVolume(const PlanningProblem& problem, IntersectionVolume& volume, VolumeMeasure measure,
                                     const std::vector<Pose>& path, const SmoothOptions& options);

// The largest volume along a path, densely at `step` (world units of vertex
// motion between checked poses), its first pose included. The walk stops
// once it exceeds `limit` (or leaves the bounds: +infinity), returning a
// value above the limit.
double MaxVolumeAlong(const PlanningProblem& problem, IntersectionVolume& volume, VolumeMeasure measure,
                      const std::vector<Pose>& path, double step,
                      double limit = std::numeric_limits<double>::infinity());

}  // namespace ausbau
