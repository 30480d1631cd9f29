#include "collision/mesh_depth.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "geometry/closest_point.h"

namespace ausbau {
namespace {

constexpr DegenerateTriangles kDegenerate = DegenerateTriangles::kNearestEdgePoint;
constexpr FaceWeights kWeights = FaceWeights::kDividedBySum;

// Refinement stops at this many sub-triangles per measurement: what is left
// unrefined keeps its upper bound (still an upper bound), so a pathological
// pair costs bounded work and errs on the safe side.
constexpr int kMaxSubTriangles = 1 << 20;

double AngleAt(const Eigen::Vector3d& at, const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  const Eigen::Vector3d a = u - at, b = v - at;
  const double na = a.norm(), nb = b.norm();
  if (na == 0 || nb == 0) return 0;
  return std::acos(std::clamp(a.dot(b) / (na * nb), -1.0, 1.0));
}

}  // namespace

DepthSurface::DepthSurface(const Shell& shell)
    : vertices_(shell.vertices), triangles_(shell.triangles), bvh_(shell.vertices, shell.triangles) {
  for (const auto& v : vertices_) box_.Extend(v);
  const int n = static_cast<int>(triangles_.size());
  // Consistently oriented: every directed edge once, its reverse once.
  std::map<std::pair<int, int>, int> directed;
  for (const auto& tri : triangles_)
    for (int e = 0; e < 3; ++e) ++directed[{tri[e], tri[(e + 1) % 3]}];
  oriented_ = shell.closed && !directed.empty();
  for (const auto& [edge, count] : directed) {
    const auto reverse = directed.find({edge.second, edge.first});
    if (count != 1 || reverse == directed.end() || reverse->second != 1) oriented_ = false;
  }
  if (!oriented_) return;
  double signed_volume = 0;
  const Eigen::Vector3d c = box_.Center();
  for (const auto& tri : triangles_)
    signed_volume += (vertices_[tri[0]] - c).dot((vertices_[tri[1]] - c).cross(vertices_[tri[2]] - c));
  const double outward = signed_volume < 0 ? -1.0 : 1.0;
  face_normal_.resize(n);
  vertex_normal_.assign(vertices_.size(), Eigen::Vector3d::Zero());
  std::map<std::pair<int, int>, Eigen::Vector3d> edge_sum;
  for (int t = 0; t < n; ++t) {
    const auto& tri = triangles_[t];
    const Eigen::Vector3d& a = vertices_[tri[0]];
    const Eigen::Vector3d& b = vertices_[tri[1]];
    const Eigen::Vector3d& cc = vertices_[tri[2]];
    const Eigen::Vector3d cross = (b - a).cross(cc - a);
    const double norm = cross.norm();
    face_normal_[t] = norm > 0 ? Eigen::Vector3d(outward * cross / norm) : Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      const int i = tri[k], j = tri[(k + 1) % 3], l = tri[(k + 2) % 3];
      vertex_normal_[i] += AngleAt(vertices_[i], vertices_[j], vertices_[l]) * face_normal_[t];
      // (Eigen's default constructor leaves a vector uninitialized.)
      edge_sum.try_emplace({std::min(j, l), std::max(j, l)}, Eigen::Vector3d::Zero()).first->second +=
          face_normal_[t];
    }
  }
  edge_normal_.resize(n);
  for (int t = 0; t < n; ++t) {
    const auto& tri = triangles_[t];
    for (int k = 0; k < 3; ++k) {
      const int j = tri[(k + 1) % 3], l = tri[(k + 2) % 3];
      edge_normal_[t][k] = edge_sum[{std::min(j, l), std::max(j, l)}];
    }
  }
}

double DepthSurface::WindingNumber(const Eigen::Vector3d& p) const {
  double sum = 0;
  for (const auto& tri : triangles_) {
    const Eigen::Vector3d a = vertices_[tri[0]] - p, b = vertices_[tri[1]] - p, c = vertices_[tri[2]] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double numerator = a.dot(b.cross(c));
    const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    sum += 2 * std::atan2(numerator, denominator);  // Van Oosterom and Strackee
  }
  return sum / (4 * M_PI);
}

bool DepthSurface::Inside(const Eigen::Vector3d& p, const TriangleBvh::Nearest& nearest) const {
  if (nearest.triangle < 0 || nearest.distance_squared == 0) return false;
  if (!oriented_) return std::abs(WindingNumber(p)) > 0.5;
  const auto& tri = triangles_[nearest.triangle];
  Eigen::Vector3d weights;
  ClosestPointOnTriangle(p, vertices_[tri[0]], vertices_[tri[1]], vertices_[tri[2]], kDegenerate, kWeights, &weights);
  // The nearest feature: a corner (two weights 0), an edge (one) or the face.
  constexpr double kZero = 1e-12;
  int zeros = 0, zero = -1, one = -1;
  for (int k = 0; k < 3; ++k) {
    if (weights[k] <= kZero) ++zeros, zero = k;
    if (weights[k] >= 1 - kZero) one = k;
  }
  Eigen::Vector3d normal = face_normal_[nearest.triangle];
  if (zeros >= 2 && one >= 0) {
    normal = vertex_normal_[tri[one]];
  } else if (zeros == 1) {
    normal = edge_normal_[nearest.triangle][zero];
  }
  return (p - nearest.point).dot(normal) < 0;
}

double DepthSurface::SignedDistance(const Eigen::Vector3d& p, int* triangle) const {
  const TriangleBvh::Nearest nearest = bvh_.NearestPoint(p);
  if (triangle) *triangle = nearest.triangle;
  const double d = std::sqrt(nearest.distance_squared);
  return Inside(p, nearest) ? d : -d;
}

// The branch and bound of mesh_depth.h for one direction: the triangles of
// `a` (moved into b's coordinates by a_to_b) against `b`.
class SurfaceDepthSearch {
 public:
  SurfaceDepthSearch(const SurfaceDepthOptions& options, double floor) : options_(options), floor_(floor) {}

  // Returns false when the lower bound exceeded options.decide (stopped).
  bool Run(const DepthSurface& a, const Eigen::Isometry3d& a_to_b, const DepthSurface& b,
           const Eigen::Isometry3d& b_to_world) {
    const Eigen::Isometry3d b_to_a = a_to_b.inverse();
    hint_ = -1;
    stack_.clear();
    Aabb query;
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3d p((corner & 1) ? b.box_.max.x() : b.box_.min.x(),
                              (corner & 2) ? b.box_.max.y() : b.box_.min.y(),
                              (corner & 4) ? b.box_.max.z() : b.box_.min.z());
      query.Extend(b_to_a * p);
    }
    std::vector<int> candidates;
    a.bvh_.ForEachTriangleNear(query.min, query.max, [&](int t) { candidates.push_back(t); });
    for (int t : candidates) {
      const auto& tri = a.triangles_[t];
      stack_.push_back({a_to_b * a.vertices_[tri[0]], a_to_b * a.vertices_[tri[1]], a_to_b * a.vertices_[tri[2]]});
      if (!Refine(b, b_to_world)) return false;
    }
    return true;
  }

  SurfaceDepth result;

 private:
  using Corners = std::array<Eigen::Vector3d, 3>;

  bool Refine(const DepthSurface& b, const Eigen::Isometry3d& b_to_world) {
    while (!stack_.empty()) {
      const Corners t = stack_.back();
      stack_.pop_back();
      const Eigen::Vector3d m = (t[0] + t[1] + t[2]) / 3.0;
      double radius = 0;
      for (const auto& c : t) radius = std::max(radius, (c - m).norm());
      const TriangleBvh::Nearest nearest = b.bvh_.NearestPoint(m, hint_);
      if (nearest.triangle < 0) continue;
      hint_ = nearest.triangle;
      const double d = std::sqrt(nearest.distance_squared);
      const bool inside = b.Inside(m, nearest);
      if (!inside && d >= radius) continue;  // wholly outside b
      if (inside) {
        result.lower = std::max(result.lower, d);
        if (d > options_.region_depth) result.region.Extend(b_to_world * m);
        if (result.lower > options_.decide) return false;
      }
      double upper = inside ? d + radius : radius;
      const auto& f = b.triangles_[nearest.triangle];
      double face_bound = 0;
      for (const auto& c : t) {
        const Eigen::Vector3d x =
            ClosestPointOnTriangle(c, b.vertices_[f[0]], b.vertices_[f[1]], b.vertices_[f[2]], kDegenerate, kWeights);
        face_bound = std::max(face_bound, (c - x).norm());
      }
      upper = std::min(upper, face_bound);
      // Measuring (decide infinite): within the resolution of the best
      // lower bound. Deciding: also below the threshold.
      const bool settled = upper <= result.lower + options_.resolution ||
                           (std::isfinite(options_.decide) && upper <= options_.decide);
      if (settled || radius < floor_ || ++made_ > kMaxSubTriangles) {
        result.upper = std::max(result.upper, upper);
        continue;
      }
      const Eigen::Vector3d ab = 0.5 * (t[0] + t[1]), bc = 0.5 * (t[1] + t[2]), ca = 0.5 * (t[2] + t[0]);
      stack_.push_back({t[0], ab, ca});
      stack_.push_back({ab, t[1], bc});
      stack_.push_back({ca, bc, t[2]});
      stack_.push_back({ab, bc, ca});
    }
    return true;
  }

  SurfaceDepthOptions options_;
  double floor_;
  std::vector<Corners> stack_;
  int hint_ = -1;
  int made_ = 0;
};

SurfaceDepth MeasureSurfaceDepth(const DepthSurface& a, const Eigen::Isometry3d& pose_a, const DepthSurface& b,
                                 const SurfaceDepthOptions& options) {
  // Sub-triangles smaller than this are not made (their bound is kept).
  const double scale = std::max(a.box().Diagonal(), b.box().Diagonal());
  const double floor = std::max(options.resolution / 8, 1e-9 * scale);
  SurfaceDepthSearch search(options, floor);
  if (search.Run(a, pose_a, b, Eigen::Isometry3d::Identity())) search.Run(b, pose_a.inverse(), a, pose_a);
  SurfaceDepth out = search.result;
  out.upper = std::max(out.upper, out.lower);
  return out;
}

}  // namespace ausbau
