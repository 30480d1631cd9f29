// A pose for tests: a translation and a turn about an axis (z by default).
#pragma once

#include <Eigen/Geometry>

#include "geometry/pose.h"

namespace ausbau::testing {

inline Pose PoseAt(double x, double y, double z, double angle = 0,
                   const Eigen::Vector3d& axis = Eigen::Vector3d::UnitZ()) {
  Pose p;
  p.t = {x, y, z};
  p.q = Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
  return p;
}

}  // namespace ausbau::testing
