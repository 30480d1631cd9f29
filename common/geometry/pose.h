// Rigid poses of the dynamic part D and their interpolation.
//
// A pose maps a point p given relative to a reference point to the world:
// x_world = R(q) p + t. Which reference point is used is the caller's
// business (see scene/scene.h: the scene convention versus the planning
// convention); this header only does the algebra.
#pragma once

#include <algorithm>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ausbau {

struct Pose {
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();  // unit, any sign

  Eigen::Vector3d Apply(const Eigen::Vector3d& p) const { return q * p + t; }
  Eigen::Isometry3d ToIsometry() const {
    Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
    iso.linear() = q.toRotationMatrix();
    iso.translation() = t;
    return iso;
  }
};

// Linear in t, spherical-linear in q along the shorter arc. s in [0, 1].
inline Pose Interpolate(const Pose& a, const Pose& b, double s) {
  Pose out;
  out.t = a.t + s * (b.t - a.t);
  out.q = a.q.slerp(s, b.q);  // Eigen's slerp takes the shorter arc
  out.q.normalize();
  return out;
}

// Rotation angle in [0, pi] between two orientations.
inline double RotationAngle(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  const double dot = std::min(1.0, std::abs(a.coeffs().dot(b.coeffs())));
  return 2.0 * std::acos(dot);
}

// Upper bound on how far any point within `radius` of the reference point
// moves along the interpolated motion from a to b: the translation plus the
// arc length of the rotation (slerp rotates about one fixed axis at constant
// speed, so a point at distance r travels at most r * angle).
inline double MaxDisplacement(const Pose& a, const Pose& b, double radius) {
  return (b.t - a.t).norm() + radius * RotationAngle(a.q, b.q);
}

// Upper bound on how far a point at `offset` from the reference point (D's
// frame) strays, along the interpolated motion from a to b, from the chord
// between its two end positions (at the same s): R(s) offset is a turn at
// constant rate through theta, whose distance to its linear interpolation
// is at most s (1 - s) / 2 x theta^2 |offset| <= theta^2 / 8 |offset| (the
// interpolation error of a C2 curve), and never more than 2 |offset|.
inline double MaxChordDeviation(const Pose& a, const Pose& b, const Eigen::Vector3d& offset) {
  const double theta = RotationAngle(a.q, b.q);
  return offset.norm() * std::min(theta * theta / 8.0, 2.0);
}

}  // namespace ausbau
