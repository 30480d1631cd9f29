#include "collision/swept_sphere.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ausbau {
namespace {

using Eigen::Vector3d;

double PointSegmentDistanceSquared(const Vector3d& p, const Vector3d& a, const Vector3d& b) {
  const Vector3d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double s = length2 > 0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (a + s * ab - p).squaredNorm();
}

// Ericson, Real-Time Collision Detection 5.1.9, with both degenerate cases.
double SegmentSegmentDistanceSquared(const Vector3d& p1, const Vector3d& q1, const Vector3d& p2, const Vector3d& q2) {
  const Vector3d d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  if (a <= 0 && e <= 0) return r.squaredNorm();
  if (a <= 0) return PointSegmentDistanceSquared(p1, p2, q2);
  if (e <= 0) return PointSegmentDistanceSquared(p2, p1, q1);
  const double c = d1.dot(r), b = d1.dot(d2), denominator = a * e - b * b;
  double s = denominator > 0 ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0) {
    t = 0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1) {
    t = 1;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  return (p1 + s * d1 - (p2 + t * d2)).squaredNorm();
}

// Distance from p to the plane region of a non-degenerate triangle, when
// p projects inside it (else +infinity: then an edge is nearer).
double PointInsideTriangleDistanceSquared(const Vector3d& p, const Vector3d& a, const Vector3d& b, const Vector3d& c,
                                          const Vector3d& normal) {
  // Inside when p's projection lies on the inner side of all three edges.
  if ((b - a).cross(p - a).dot(normal) < 0 || (c - b).cross(p - b).dot(normal) < 0 ||
      (a - c).cross(p - c).dot(normal) < 0) {
    return std::numeric_limits<double>::infinity();
  }
  const double height = (p - a).dot(normal);
  return height * height / normal.squaredNorm();
}

// Whether the segment crosses the triangle's plane inside the triangle
// (not parallel to it; a parallel segment is left to the edge distances).
// Tolerant on the side of "crosses".
bool SegmentCrossesTriangle(const Vector3d& p0, const Vector3d& p1, const Vector3d& a, const Vector3d& b,
                            const Vector3d& c, const Vector3d& normal) {
  const double h0 = (p0 - a).dot(normal), h1 = (p1 - a).dot(normal);
  if ((h0 > 0 && h1 > 0) || (h0 < 0 && h1 < 0) || h0 == h1) return false;
  const Vector3d x = p0 + (h0 / (h0 - h1)) * (p1 - p0);
  const double slack = -1e-12 * normal.squaredNorm();
  return (b - a).cross(x - a).dot(normal) >= slack && (c - b).cross(x - b).dot(normal) >= slack &&
         (a - c).cross(x - c).dot(normal) >= slack;
}

}  // namespace

double SegmentTriangleDistanceSquared(const Vector3d& p0, const Vector3d& p1, const Vector3d& a, const Vector3d& b,
                                      const Vector3d& c) {
  // Where segment and triangle do not meet, the nearest pair has an end of
  // the segment or a point of the triangle's boundary: if both were inner
  // points, the line between them would be normal to the plane and to the
  // segment, so the segment would be parallel to the plane and could slide
  // to one of those.
  double best = std::min({SegmentSegmentDistanceSquared(p0, p1, a, b), SegmentSegmentDistanceSquared(p0, p1, b, c),
                          SegmentSegmentDistanceSquared(p0, p1, c, a)});
  const Vector3d normal = (b - a).cross(c - a);
  const double scale2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  if (normal.squaredNorm() <= 1e-24 * scale2 * scale2) return best;  // degenerate: its edges are all of it
  if (SegmentCrossesTriangle(p0, p1, a, b, c, normal)) return 0;
  best = std::min(best, PointInsideTriangleDistanceSquared(p0, a, b, c, normal));
  return std::min(best, PointInsideTriangleDistanceSquared(p1, a, b, c, normal));
}

TriangleTree::TriangleTree(std::vector<std::array<Vector3d, 3>> triangles) : triangles_(std::move(triangles)) {
  if (!triangles_.empty()) Build(0, static_cast<int>(triangles_.size()));
}

int TriangleTree::Build(int first, int count) {
  constexpr int kLeafSize = 4;
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Vector3d min = Vector3d::Constant(std::numeric_limits<double>::infinity()), max = -min;
  Vector3d centroid_min = min, centroid_max = max;
  for (int i = first; i < first + count; ++i) {
    const Vector3d centroid = (triangles_[i][0] + triangles_[i][1] + triangles_[i][2]) / 3.0;
    centroid_min = centroid_min.cwiseMin(centroid);
    centroid_max = centroid_max.cwiseMax(centroid);
    for (const Vector3d& v : triangles_[i]) {
      min = min.cwiseMin(v);
      max = max.cwiseMax(v);
    }
  }
  nodes_[index].min = min;
  nodes_[index].max = max;
  nodes_[index].first = first;
  nodes_[index].count = count;
  if (count <= kLeafSize) return index;
  int axis = 0;
  (centroid_max - centroid_min).maxCoeff(&axis);
  const int half = count / 2;
  auto key = [axis](const std::array<Vector3d, 3>& t) { return t[0][axis] + t[1][axis] + t[2][axis]; };
  std::nth_element(triangles_.begin() + first, triangles_.begin() + first + half, triangles_.begin() + first + count,
                   [&key](const auto& l, const auto& r) { return key(l) < key(r); });
  const int left = Build(first, half);
  const int right = Build(first + half, count - half);
  nodes_[index].left = left;
  nodes_[index].right = right;
  nodes_[index].count = 0;
  return index;
}

bool TriangleTree::AnyWithin(const Vector3d& p0, const Vector3d& p1, double radius) const {
  if (nodes_.empty()) return false;
  const Vector3d low = p0.cwiseMin(p1) - Vector3d::Constant(radius);
  const Vector3d high = p0.cwiseMax(p1) + Vector3d::Constant(radius);
  const double radius2 = radius * radius;
  // Whether a node may hold a triangle within `radius`: its box meets the
  // capsule's box, and the segment's distance to the box's centre is not
  // more than the radius plus the box's half diagonal.
  auto may_hold = [&](const Node& node) {
    if ((node.min.array() > high.array()).any() || (node.max.array() < low.array()).any()) return false;
    const double reach = radius + 0.5 * (node.max - node.min).norm();
    return PointSegmentDistanceSquared(0.5 * (node.min + node.max), p0, p1) <= reach * reach;
  };
  int stack[128];
  int size = 0;
  if (may_hold(nodes_[0])) stack[size++] = 0;
  while (size > 0) {
    const Node& node = nodes_[stack[--size]];
    if (node.left < 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        const auto& t = triangles_[i];
        if (SegmentTriangleDistanceSquared(p0, p1, t[0], t[1], t[2]) <= radius2) return true;
      }
      continue;
    }
    // The tree is balanced (median splits), so 128 levels are never reached.
    if (may_hold(nodes_[node.right])) stack[size++] = node.right;
    if (may_hold(nodes_[node.left])) stack[size++] = node.left;
  }
  return false;
}

BoundingSphere BoundingSphere::Of(const std::vector<Vector3d>& vertices) {
  BoundingSphere sphere;
  if (vertices.empty()) return sphere;
  Vector3d min = vertices[0], max = min;
  for (const Vector3d& v : vertices) {
    min = min.cwiseMin(v);
    max = max.cwiseMax(v);
  }
  sphere.centre = 0.5 * (min + max);
  for (const Vector3d& v : vertices) sphere.radius = std::max(sphere.radius, (v - sphere.centre).norm());
  return sphere;
}

bool SweptSphereClear(const BoundingSphere& sphere, const TriangleTree& environment, const Pose& a, const Pose& b,
                      double margin) {
  const double theta = RotationAngle(a.q, b.q);
  const double bend = std::min(theta * theta / 8.0, 2.0);
  const double radius = sphere.radius + sphere.centre.norm() * bend + margin;
  return !environment.AnyWithin(a.Apply(sphere.centre), b.Apply(sphere.centre), radius);
}

}  // namespace ausbau
