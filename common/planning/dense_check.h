// An independent re-check of a finished path: its own FCL models of the
// scene meshes in their original coordinates, its own interpolation, and a
// step bound: between two checked poses no vertex of D moves more than
// `step_fraction` x D's AABB diagonal. Used by `ausbau-plan --verify`, by
// `ausbau-smooth` and by the end-to-end tests.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "geometry/pose.h"

namespace ausbau {

struct Scene;

struct DenseCheckReport {
  bool valid = true;
  std::int64_t poses_checked = 0;
  int first_bad_segment = -1;        // index of the segment starting at that waypoint
  double first_bad_fraction = 0;     // where on it
  std::string reason;                // empty when valid
  bool stopped_by_deadline = false;  // not valid because the deadline came first
};

// `waypoints` are in the scene convention; consecutive waypoints are
// interpolated about `reference_point` (D's mesh coordinates), linear in t
// and slerp in q. Also checks that every checked pose keeps the scene's
// bounds when it has any. `deadline`: a check still running then stops, not
// valid (a path billions of steps long, across bounds of 1e9, would take
// hours); none by default.
DenseCheckReport DenseCheckPath(
    const Scene& scene, const Eigen::Vector3d& reference_point, const std::vector<Pose>& waypoints,
    double step_fraction,
    std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max());

}  // namespace ausbau
