#include "collision/swept_sphere.h"

#include <algorithm>

namespace ausbau {

BoundingSphere BoundingSphere::Of(const std::vector<Eigen::Vector3d>& vertices) {
  BoundingSphere sphere;
  if (vertices.empty()) return sphere;
  Eigen::Vector3d min = vertices[0], max = min;
  for (const Eigen::Vector3d& v : vertices) {
    min = min.cwiseMin(v);
    max = max.cwiseMax(v);
  }
  sphere.centre = 0.5 * (min + max);
  for (const Eigen::Vector3d& v : vertices) sphere.radius = std::max(sphere.radius, (v - sphere.centre).norm());
  return sphere;
}

bool SweptSphereClear(const BoundingSphere& sphere, const TriangleBvh& environment, const Pose& a, const Pose& b,
                      double margin) {
  const double radius = sphere.radius + MaxChordDeviation(a, b, sphere.centre) + margin;
  return !environment.AnyWithinSegment(a.Apply(sphere.centre), b.Apply(sphere.centre), radius);
}

}  // namespace ausbau
