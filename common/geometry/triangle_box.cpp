#include "geometry/triangle_box.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace ausbau {

bool TriangleOverlapsBox(const Eigen::Vector3d& center, const Eigen::Vector3d& half, const Eigen::Vector3d& a,
                         const Eigen::Vector3d& b, const Eigen::Vector3d& c, SatRounding rounding) {
  using Vec3 = Eigen::Vector3d;
  const bool cube = rounding == SatRounding::kCubeHalfSize;
  // The triangle relative to the box's centre.
  const Vec3 v0 = a - center, v1 = b - center, v2 = c - center;
  // The box's face normals.
  for (int k = 0; k < 3; ++k) {
    const double lo = std::min({v0[k], v1[k], v2[k]}), hi = std::max({v0[k], v1[k], v2[k]});
    if (lo > half[k] || hi < -half[k]) return false;
  }
  const Vec3 edges[3] = {v1 - v0, v2 - v1, v0 - v2};
  // Box axis e_k x edge.
  for (const Vec3& edge : edges) {
    for (int k = 0; k < 3; ++k) {
      const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
      Vec3 axis = Vec3::Zero();
      axis[k1] = -edge[k2];
      axis[k2] = edge[k1];
      double r;
      if (cube) {
        r = half[0] * axis.cwiseAbs().sum();
        if (r == 0) continue;
      } else {
        r = half[k1] * std::abs(axis[k1]) + half[k2] * std::abs(axis[k2]);
      }
      const double p0 = axis.dot(v0), p1 = axis.dot(v1), p2 = axis.dot(v2);
      if (std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r) return false;
    }
  }
  // The triangle's normal.
  if (cube) {
    const Vec3 n = edges[0].cross(edges[1]);
    return !(std::abs(n.dot(v0)) > half[0] * n.cwiseAbs().sum());
  }
  const Vec3 n = edges[0].cross(v2 - v0);
  return std::abs(n.dot(v0)) <= half.dot(n.cwiseAbs());
}

}  // namespace ausbau
