// The axis-aligned box of a box carried by a rigid motion.
#pragma once

#include <Eigen/Geometry>

#include "geometry/mesh.h"
#include "geometry/pose.h"

namespace ausbau {

// The axis-aligned box of the box `local` turned and moved by `pose`: its
// centre moves, its half-extents go through |R|. Conservative for anything
// inside `local` (the box of its corners).
inline Aabb PlacedBox(const Aabb& local, const Pose& pose) {
  const Eigen::Matrix3d rotation = pose.q.toRotationMatrix();
  const Eigen::Vector3d center = rotation * local.Center() + pose.t;
  const Eigen::Vector3d half = rotation.cwiseAbs() * (0.5 * local.Size());
  Aabb box;
  box.min = center - half;
  box.max = center + half;
  return box;
}

}  // namespace ausbau
