#include "geometry/winding_bvh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "geometry/closest_point.h"

namespace ausbau {
namespace {

using Vec3 = Eigen::Vector3d;

// Signed solid angle of triangle (a, b, c) seen from the origin (Van Oosterom
// and Strackee 1983): positive when the origin is behind the triangle (its
// counter-clockwise side faces away).
double SolidAngle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double num = a.dot(b.cross(c));
  const double den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
  return 2.0 * std::atan2(num, den);
}

double BoxDistanceSquared(const Aabb& box, const Vec3& p) {
  const Vec3 d = (box.min - p).cwiseMax(p - box.max).cwiseMax(Vec3::Zero());
  return d.squaredNorm();
}

}  // namespace

WindingBvh::WindingBvh(const TriangleMesh& mesh, const std::vector<int>* triangles, const std::vector<bool>* flip) {
  std::vector<int> ids;
  if (triangles != nullptr) {
    ids = *triangles;
  } else {
    ids.resize(mesh.triangles.size());
    std::iota(ids.begin(), ids.end(), 0);
  }
  tris_.reserve(ids.size());
  for (int t : ids) {
    const auto& tri = mesh.triangles[t];
    const bool f = flip != nullptr && (*flip)[t];
    tris_.push_back({mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]], t, f ? -1.0 : 1.0});
  }
  if (tris_.empty()) return;
  nodes_.reserve(2 * tris_.size() / 4 + 1);
  nodes_.push_back({});
  nodes_[0].begin = 0;
  nodes_[0].end = static_cast<int>(tris_.size());
  std::vector<int> stack = {0};
  while (!stack.empty()) {
    const int id = stack.back();
    stack.pop_back();
    Node node = nodes_[id];
    double area = 0;
    Aabb centroids;
    for (int t = node.begin; t < node.end; ++t) {
      const Tri& tri = tris_[t];
      node.box.Extend(tri.a);
      node.box.Extend(tri.b);
      node.box.Extend(tri.c);
      const Vec3 vector_area = 0.5 * (tri.b - tri.a).cross(tri.c - tri.a);
      const double a = vector_area.norm();
      const Vec3 centroid = (tri.a + tri.b + tri.c) / 3.0;
      node.area_normal += tri.sign * vector_area;
      node.center += a * centroid;
      area += a;
      centroids.Extend(centroid);
    }
    node.center = area > 0 ? Vec3(node.center / area) : centroids.Center();
    node.area = area;
    for (int t = node.begin; t < node.end; ++t) {
      for (const Vec3* v : {&tris_[t].a, &tris_[t].b, &tris_[t].c}) {
        node.radius = std::max(node.radius, (*v - node.center).norm());
      }
    }
    if (node.end - node.begin > 8) {
      int axis = 0;
      centroids.Size().maxCoeff(&axis);
      const int mid = (node.begin + node.end) / 2;
      std::nth_element(tris_.begin() + node.begin, tris_.begin() + mid, tris_.begin() + node.end,
                       [axis](const Tri& x, const Tri& y) {
                         return x.a[axis] + x.b[axis] + x.c[axis] < y.a[axis] + y.b[axis] + y.c[axis];
                       });
      node.left = static_cast<int>(nodes_.size());
      node.right = node.left + 1;
      Node left, right;
      left.begin = node.begin;
      left.end = mid;
      right.begin = mid;
      right.end = node.end;
      nodes_.push_back(left);
      nodes_.push_back(right);
      stack.push_back(node.left);
      stack.push_back(node.right);
    }
    nodes_[id] = node;
  }
}

template <typename Far>
WindingBvh::Estimate WindingBvh::HierarchicalSum(const Vec3& p, const Far& far) const {
  Estimate estimate;
  if (tris_.empty()) return estimate;
  double omega = 0, error = 0;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    const Vec3 d = n.center - p;
    const double dist = d.norm();
    const double gap = dist - n.radius;
    // How far the dipole term may be off (winding_bvh.h), in steradians.
    const double bound = gap > 0 ? 2 * n.area * n.radius / (gap * gap * gap) : 0.0;
    if (far(n, dist, gap, bound)) {
      omega += n.area_normal.dot(d) / (dist * dist * dist);
      error += gap > 0 ? bound : std::numeric_limits<double>::infinity();
    } else if (n.left < 0) {
      for (int t = n.begin; t < n.end; ++t) {
        const Tri& tri = tris_[t];
        omega += tri.sign * SolidAngle(tri.a - p, tri.b - p, tri.c - p);
      }
    } else {
      stack[top++] = n.left;
      stack[top++] = n.right;
    }
  }
  estimate.value = omega / (4.0 * M_PI);
  estimate.error_bound = error / (4.0 * M_PI);
  return estimate;
}

double WindingBvh::WindingNumber(const Vec3& p, double beta) const {
  return HierarchicalSum(p, [beta](const Node& n, double dist, double, double) { return dist > beta * n.radius; })
      .value;
}

double WindingBvh::WindingNumberExact(const Vec3& p) const {
  double omega = 0;
  for (const Tri& tri : tris_) omega += tri.sign * SolidAngle(tri.a - p, tri.b - p, tri.c - p);
  return omega / (4.0 * M_PI);
}

WindingBvh::Estimate WindingBvh::EstimateWindingNumber(const Vec3& p, double node_error) const {
  const double allowed = 4.0 * M_PI * node_error;  // in steradians, as the sums
  return HierarchicalSum(
      p, [allowed](const Node&, double, double gap, double bound) { return gap > 0 && bound <= allowed; });
}

bool WindingBvh::AbsoluteWindingExceeds(const Vec3& p, double threshold, double node_error) const {
  const Estimate estimate = EstimateWindingNumber(p, node_error);
  const double winding = std::abs(estimate.value);
  if (std::abs(winding - threshold) > estimate.error_bound) return winding > threshold;
  return std::abs(WindingNumberExact(p)) > threshold;
}

WindingBvh::Closest WindingBvh::ClosestPoint(const Vec3& p) const {
  Closest best;
  if (tris_.empty()) return best;
  double best_d2 = std::numeric_limits<double>::infinity();
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (BoxDistanceSquared(n.box, p) >= best_d2) continue;
    if (n.left < 0) {
      for (int t = n.begin; t < n.end; ++t) {
        const Tri& tri = tris_[t];
        // The voxelizer's arithmetic, as its results were recorded: a
        // triangle without area answers its nearest corner.
        Vec3 bary;
        const Vec3 q = ClosestPointOnTriangle(p, tri.a, tri.b, tri.c, DegenerateTriangles::kNearestCorner,
                                              FaceWeights::kDividedBySum, &bary);
        const double d2 = (q - p).squaredNorm();
        if (d2 < best_d2) {
          best_d2 = d2;
          best.triangle = tri.id;
          best.point = q;
          best.barycentric = bary;
        }
      }
    } else {
      // Nearer child last, so that it is visited first.
      const double dl = BoxDistanceSquared(nodes_[n.left].box, p), dr = BoxDistanceSquared(nodes_[n.right].box, p);
      if (dl < dr) {
        stack[top++] = n.right;
        stack[top++] = n.left;
      } else {
        stack[top++] = n.left;
        stack[top++] = n.right;
      }
    }
  }
  best.distance = std::sqrt(best_d2);
  return best;
}

}  // namespace ausbau
