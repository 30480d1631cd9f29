#include "geometry/triangle_bvh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "geometry/closest_point.h"
#include "geometry/mesh.h"

namespace ausbau {
namespace {

// The closest-point arithmetic of the labeling's BVH as it was recorded: its
// triangles have positive area (BuildMeshTopology drops the others), so the
// divisions are not guarded.
constexpr DegenerateTriangles kDegenerate = DegenerateTriangles::kUnguarded;
constexpr FaceWeights kFaceWeights = FaceWeights::kTimesReciprocalOfSum;

}  // namespace

TriangleBvh::TriangleBvh(const std::vector<Eigen::Vector3d>& vertices,
                         const std::vector<std::array<int, 3>>& triangles) {
  const int m = static_cast<int>(triangles.size());
  if (m == 0) return;
  std::vector<Eigen::Vector3d> centroids(m);
  for (int t = 0; t < m; ++t) {
    centroids[t] = (vertices[triangles[t][0]] + vertices[triangles[t][1]] + vertices[triangles[t][2]]) / 3.0;
  }
  std::vector<int> order(m);
  std::iota(order.begin(), order.end(), 0);
  nodes_.reserve(2 * static_cast<std::size_t>(m) / 2 + 8);
  nodes_.push_back(Node{});
  a_.resize(m);
  b_.resize(m);
  c_.resize(m);
  id_.resize(m);
  // Build permutes `order`; afterwards fill the leaf arrays in that order.
  Build(0, 0, m, order, centroids);
  slot_of_id_.resize(m);
  for (int s = 0; s < m; ++s) {
    const auto& tri = triangles[order[s]];
    a_[s] = vertices[tri[0]];
    b_[s] = vertices[tri[1]];
    c_[s] = vertices[tri[2]];
    id_[s] = order[s];
    slot_of_id_[order[s]] = s;
  }
  // Leaf boxes: recomputed from the triangles (Build used the order only).
  for (int i = static_cast<int>(nodes_.size()) - 1; i >= 0; --i) {
    Node& node = nodes_[i];
    Aabb box;
    if (node.count > 0) {
      for (int s = node.first; s < node.first + node.count; ++s) {
        box.Extend(a_[s]);
        box.Extend(b_[s]);
        box.Extend(c_[s]);
      }
    } else {
      for (int child = node.first; child <= node.first + 1; ++child) {
        box.Extend(Eigen::Vector3d(nodes_[child].min[0], nodes_[child].min[1], nodes_[child].min[2]));
        box.Extend(Eigen::Vector3d(nodes_[child].max[0], nodes_[child].max[1], nodes_[child].max[2]));
      }
    }
    for (int k = 0; k < 3; ++k) {
      node.min[k] = box.min[k];
      node.max[k] = box.max[k];
    }
  }
}

void TriangleBvh::Build(int index, int begin, int end, std::vector<int>& order,
                        const std::vector<Eigen::Vector3d>& centroids) {
  if (end - begin <= 4) {
    nodes_[index].first = begin;
    nodes_[index].count = end - begin;
    return;
  }
  Aabb box;
  for (int i = begin; i < end; ++i) box.Extend(centroids[order[i]]);
  int axis = 0;
  const Eigen::Vector3d size = box.Size();
  if (size.y() > size[axis]) axis = 1;
  if (size.z() > size[axis]) axis = 2;
  const int middle = begin + (end - begin) / 2;
  std::nth_element(order.begin() + begin, order.begin() + middle, order.begin() + end, [&](int x, int y) {
    const double cx = centroids[x][axis], cy = centroids[y][axis];
    return cx != cy ? cx < cy : x < y;
  });
  // Children next to each other: left at `first`, right at `first + 1`.
  const int left = static_cast<int>(nodes_.size());
  nodes_.push_back(Node{});
  nodes_.push_back(Node{});
  nodes_[index].first = left;
  nodes_[index].count = 0;
  Build(left, begin, middle, order, centroids);
  Build(left + 1, middle, end, order, centroids);
}

namespace {

inline double BoxDistanceSquared(const double* min, const double* max, const Eigen::Vector3d& q) {
  double d2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double below = min[k] - q[k], above = q[k] - max[k];
    const double d = below > 0 ? below : (above > 0 ? above : 0.0);
    d2 += d * d;
  }
  return d2;
}

}  // namespace

template <typename Skip>
TriangleBvh::Nearest TriangleBvh::Search(const Eigen::Vector3d& q, Nearest best, const Skip& skip) const {
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (BoxDistanceSquared(node.min, node.max, q) >= best.distance_squared) continue;
    if (node.count > 0) {
      for (int s = node.first; s < node.first + node.count; ++s) {
        if (skip(id_[s])) continue;
        const Eigen::Vector3d point = ClosestPointOnTriangle(q, a_[s], b_[s], c_[s], kDegenerate, kFaceWeights);
        const double d2 = (point - q).squaredNorm();
        if (d2 < best.distance_squared) {
          best.distance_squared = d2;
          best.point = point;
          best.triangle = id_[s];
        }
      }
      continue;
    }
    const int left = node.first, right = node.first + 1;
    const double dl = BoxDistanceSquared(nodes_[left].min, nodes_[left].max, q);
    const double dr = BoxDistanceSquared(nodes_[right].min, nodes_[right].max, q);
    // Push the farther child first so that the nearer one is searched first.
    if (dl <= dr) {
      if (dr < best.distance_squared) stack[top++] = right;
      if (dl < best.distance_squared) stack[top++] = left;
    } else {
      if (dl < best.distance_squared) stack[top++] = left;
      if (dr < best.distance_squared) stack[top++] = right;
    }
  }
  return best;
}

TriangleBvh::Nearest TriangleBvh::NearestPoint(const Eigen::Vector3d& q, int hint) const {
  Nearest best;
  if (nodes_.empty()) return best;
  if (hint >= 0 && hint < TriangleCount()) {
    // Start the bound from the hinted triangle. The search then finds it again
    // (or a strictly nearer one): the answer does not depend on the hint.
    const int s = slot_of_id_[hint];
    const Eigen::Vector3d point = ClosestPointOnTriangle(q, a_[s], b_[s], c_[s], kDegenerate, kFaceWeights);
    best.distance_squared = std::nextafter((point - q).squaredNorm(), std::numeric_limits<double>::infinity());
  }
  return Search(q, best, [](int) { return false; });
}

TriangleBvh::Nearest TriangleBvh::NearestPoint(const Eigen::Vector3d& q, const std::function<bool(int)>& skip) const {
  if (nodes_.empty()) return Nearest{};
  return Search(q, Nearest{}, skip);
}

void TriangleBvh::ForEachTriangleNear(const Eigen::Vector3d& min, const Eigen::Vector3d& max,
                                      const std::function<bool(int)>& visit) const {
  if (nodes_.empty()) return;
  const auto overlaps = [&](const double* lo, const double* hi) {
    for (int k = 0; k < 3; ++k)
      if (hi[k] < min[k] || max[k] < lo[k]) return false;
    return true;
  };
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (!overlaps(node.min, node.max)) continue;
    if (node.count == 0) {
      stack[top++] = node.first + 1;
      stack[top++] = node.first;
      continue;
    }
    for (int s = node.first; s < node.first + node.count; ++s) {
      const Eigen::Vector3d lo = a_[s].cwiseMin(b_[s]).cwiseMin(c_[s]), hi = a_[s].cwiseMax(b_[s]).cwiseMax(c_[s]);
      if (overlaps(lo.data(), hi.data()) && !visit(id_[s])) return;
    }
  }
}

bool TriangleBvh::AnyWithinSegment(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, double radius) const {
  if (nodes_.empty()) return false;
  const Eigen::Vector3d low = p0.cwiseMin(p1).array() - radius, high = p0.cwiseMax(p1).array() + radius;
  const double radius2 = radius * radius;
  const Eigen::Vector3d axis = p1 - p0;
  const double length2 = axis.squaredNorm();
  // Whether a node may hold a triangle within `radius`: its box meets the
  // capsule's box, and the segment comes within the radius plus the box's
  // half diagonal of the box's centre.
  const auto may_hold = [&](const Node& node) {
    const Eigen::Vector3d lo(node.min[0], node.min[1], node.min[2]), hi(node.max[0], node.max[1], node.max[2]);
    if ((lo.array() > high.array()).any() || (hi.array() < low.array()).any()) return false;
    const Eigen::Vector3d centre = 0.5 * (lo + hi);
    const double s = length2 > 0 ? std::clamp((centre - p0).dot(axis) / length2, 0.0, 1.0) : 0.0;
    const double reach = radius + 0.5 * (hi - lo).norm();
    return (p0 + s * axis - centre).squaredNorm() <= reach * reach;
  };
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (!may_hold(node)) continue;
    if (node.count == 0) {
      stack[top++] = node.first + 1;
      stack[top++] = node.first;
      continue;
    }
    for (int s = node.first; s < node.first + node.count; ++s) {
      if (SegmentTriangleDistanceSquared(p0, p1, a_[s], b_[s], c_[s]) <= radius2) return true;
    }
  }
  return false;
}

int TriangleBvh::CountCrossings(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double t_min,
                                const std::function<bool(int)>& skip) const {
  if (nodes_.empty()) return 0;
  Eigen::Vector3d inverse;
  for (int k = 0; k < 3; ++k) inverse[k] = 1.0 / direction[k];
  int crossings = 0;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    double t0 = t_min, t1 = std::numeric_limits<double>::infinity();
    bool hit = true;
    for (int k = 0; k < 3 && hit; ++k) {
      double ta = (node.min[k] - origin[k]) * inverse[k];
      double tb = (node.max[k] - origin[k]) * inverse[k];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
      hit = t0 <= t1;
    }
    if (!hit) continue;
    if (node.count == 0) {
      stack[top++] = node.first;
      stack[top++] = node.first + 1;
      continue;
    }
    for (int s = node.first; s < node.first + node.count; ++s) {
      if (skip && skip(id_[s])) continue;
      // Moeller-Trumbore.
      const Eigen::Vector3d e1 = b_[s] - a_[s], e2 = c_[s] - a_[s];
      const Eigen::Vector3d pv = direction.cross(e2);
      const double det = e1.dot(pv);
      if (std::abs(det) < 1e-300) continue;
      const double inv_det = 1.0 / det;
      const Eigen::Vector3d tv = origin - a_[s];
      const double u = tv.dot(pv) * inv_det;
      if (u < 0 || u > 1) continue;
      const Eigen::Vector3d qv = tv.cross(e1);
      const double v = direction.dot(qv) * inv_det;
      if (v < 0 || u + v > 1) continue;
      const double t = e2.dot(qv) * inv_det;
      if (t > t_min) ++crossings;
    }
  }
  return crossings;
}

}  // namespace ausbau
