#include "geometry/protrusions.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <utility>

#include "core/format.h"
#include "geometry/principal_axes.h"

namespace ausbau {
namespace {

// A face of the plate: coplanar triangles facing one way along n.
struct PlaneFace {
  double offset = 0;  // area-weighted
  double area = 0;
};

// The faces facing `sign` n, grouped by offset (a new group where the next
// offset is more than eps above the last one's).
std::vector<PlaneFace> FacesAlong(const Eigen::Vector3d& n, int sign, const std::vector<Eigen::Vector3d>& normal,
                                  const std::vector<double>& area, const std::vector<Eigen::Vector3d>& centroid,
                                  double cos_parallel, double eps) {
  std::vector<std::pair<double, double>> offsets;  // (offset, area)
  for (std::size_t t = 0; t < normal.size(); ++t)
    if (area[t] > 0 && sign * n.dot(normal[t]) >= cos_parallel) offsets.emplace_back(n.dot(centroid[t]), area[t]);
  std::sort(offsets.begin(), offsets.end());
  std::vector<PlaneFace> faces;
  double last = -std::numeric_limits<double>::infinity();
  double weighted = 0;
  for (const auto& [offset, a] : offsets) {
    if (faces.empty() || offset - last > eps) {
      if (!faces.empty()) faces.back().offset = weighted / faces.back().area;
      faces.push_back({});
      weighted = 0;
    }
    faces.back().area += a;
    weighted += a * offset;
    last = offset;
  }
  if (!faces.empty()) faces.back().offset = weighted / faces.back().area;
  return faces;
}

const PlaneFace& Largest(const std::vector<PlaneFace>& faces) {
  return *std::max_element(faces.begin(), faces.end(),
                           [](const PlaneFace& a, const PlaneFace& b) { return a.area < b.area; });
}

int Find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// The box of a feature's vertices (see protrusions.h, 3.).
TurnedBox FeatureBox(const Shell& shell, const std::vector<int>& triangles, const Eigen::Vector3d& n, int side,
                     double face_offset, double margin) {
  std::set<int> corners;
  for (int t : triangles)
    for (int v : shell.triangles[t]) corners.insert(v);
  std::vector<Eigen::Vector3d> in_plane;
  for (int v : corners) in_plane.push_back(shell.vertices[v] - n.dot(shell.vertices[v]) * n);
  Eigen::Vector3d u = PrincipalAxes(in_plane).col(0);
  u = (u - n.dot(u) * n);
  if (u.norm() < 1e-9) u = n.unitOrthogonal();
  u.normalize();
  const Eigen::Vector3d v = n.cross(u).normalized();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (int c : corners) {
    const Eigen::Vector3d& p = shell.vertices[c];
    const Eigen::Vector3d q(u.dot(p), v.dot(p), n.dot(p));
    lo = lo.cwiseMin(q);
    hi = hi.cwiseMax(q);
  }
  lo.head<2>().array() -= margin;
  hi.head<2>().array() += margin;
  if (side > 0) {
    lo.z() = face_offset;
    hi.z() += margin;
  } else {
    hi.z() = face_offset;
    lo.z() -= margin;
  }
  TurnedBox box;
  box.axes.col(0) = u;
  box.axes.col(1) = v;
  box.axes.col(2) = n;
  const Eigen::Vector3d mid = 0.5 * (lo + hi);
  box.center = mid.x() * u + mid.y() * v + mid.z() * n;
  box.half = 0.5 * (hi - lo);
  return box;
}

// Whether two boxes that share their third axis overlap (separating axes:
// the third, and each box's two others).
bool Overlap(const TurnedBox& a, const TurnedBox& b) {
  const Eigen::Vector3d d = b.center - a.center;
  const auto separated = [&](const Eigen::Vector3d& axis) {
    double ra = 0, rb = 0;
    for (int k = 0; k < 3; ++k) {
      ra += a.half[k] * std::abs(axis.dot(a.axes.col(k)));
      rb += b.half[k] * std::abs(axis.dot(b.axes.col(k)));
    }
    return std::abs(d.dot(axis)) > ra + rb;
  };
  return !(separated(a.axes.col(2)) || separated(a.axes.col(0)) || separated(a.axes.col(1)) ||
           separated(b.axes.col(0)) || separated(b.axes.col(1)));
}

// The volume between the feature's triangles and the plate's face plane
// (closed by the face: its tetrahedra from a point on the plane add nothing).
double FeatureVolume(const Shell& shell, const std::vector<int>& triangles, const Eigen::Vector3d& origin) {
  double six = 0;
  for (int t : triangles) {
    const auto& f = shell.triangles[t];
    six += (shell.vertices[f[0]] - origin).dot((shell.vertices[f[1]] - origin).cross(shell.vertices[f[2]] - origin));
  }
  return std::abs(six) / 6;
}

}  // namespace

PlateFeatures FindPlateFeatures(const Shell& shell) {
  PlateFeatures out;
  if (!shell.closed || shell.convex) {
    out.reason = shell.convex ? "a convex solid stands nothing out" : "not a closed solid";
    return out;
  }
  const int count = static_cast<int>(shell.triangles.size());
  const double eps = PlateRule::kEpsilonOfDiagonal * shell.box.Diagonal();
  const double cos_parallel = std::cos(PlateRule::kParallelDegrees * M_PI / 180);
  std::vector<Eigen::Vector3d> normal(count), centroid(count);
  std::vector<double> area(count);
  double total = 0;
  for (int t = 0; t < count; ++t) {
    const auto& f = shell.triangles[t];
    const Eigen::Vector3d& a = shell.vertices[f[0]];
    const Eigen::Vector3d& b = shell.vertices[f[1]];
    const Eigen::Vector3d& c = shell.vertices[f[2]];
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    area[t] = 0.5 * cross.norm();
    normal[t] = area[t] > 0 ? Eigen::Vector3d(cross.normalized()) : Eigen::Vector3d::Zero();
    centroid[t] = (a + b + c) / 3;
    total += area[t];
  }
  // 1. The direction with the most parallel area, among those of the
  // largest triangles (a plate's sides are its largest faces).
  std::vector<int> order(count);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return area[a] > area[b]; });
  constexpr int kCandidates = 16;
  std::vector<Eigen::Vector3d> candidates;
  for (int t : order) {
    if (area[t] <= 0 || static_cast<int>(candidates.size()) == kCandidates) break;
    const bool seen = std::any_of(candidates.begin(), candidates.end(),
                                  [&](const Eigen::Vector3d& c) { return std::abs(c.dot(normal[t])) >= cos_parallel; });
    if (!seen) candidates.push_back(normal[t]);
  }
  if (candidates.empty()) {
    out.reason = "no triangle has an area";
    return out;
  }
  double best_area = -1;
  Eigen::Vector3d n = candidates.front();
  for (const auto& c : candidates) {
    double parallel = 0;
    for (int t = 0; t < count; ++t)
      if (std::abs(c.dot(normal[t])) >= cos_parallel) parallel += area[t];
    if (parallel > best_area) best_area = parallel, n = c;
  }
  int largest = 0;
  n.cwiseAbs().maxCoeff(&largest);
  if (n[largest] < 0) n = -n;
  out.normal = n;

  const auto top = FacesAlong(n, +1, normal, area, centroid, cos_parallel, eps);
  const auto bottom = FacesAlong(n, -1, normal, area, centroid, cos_parallel, eps);
  if (top.empty() || bottom.empty()) {
    out.reason = "no two opposite faces";
    return out;
  }
  const PlaneFace& high = Largest(top);
  const PlaneFace& low = Largest(bottom);
  const double share = std::min(high.area, low.area) / total;
  if (share < PlateRule::kMinFaceShare || low.offset >= high.offset - eps) {
    out.reason =
        Fmt("not a plate: its largest opposite faces hold %.0f%% of its area (a plate's two sides: at least "
            "%.0f%% each)",
            100 * share, 100 * PlateRule::kMinFaceShare);
    return out;
  }
  out.low = low.offset;
  out.high = high.offset;
  const double thickness = out.high - out.low;
  const double margin = PlateRule::kMarginOfThickness * thickness;

  out.on_face.assign(count, 0);
  std::vector<int> side(count, 0);
  for (int t = 0; t < count; ++t) {
    bool on_high = true, on_low = true;
    for (int v : shell.triangles[t]) {
      const double o = n.dot(shell.vertices[v]);
      on_high = on_high && std::abs(o - out.high) <= eps;
      on_low = on_low && std::abs(o - out.low) <= eps;
    }
    out.on_face[t] = on_high || on_low;
    const double o = n.dot(centroid[t]);
    side[t] = o > out.high + eps ? 1 : (o < out.low - eps ? -1 : 0);
  }

  // 2. Features: beyond-the-plate triangles connected through shared edges.
  std::vector<int> parent(count);
  std::iota(parent.begin(), parent.end(), 0);
  std::map<std::pair<int, int>, int> first_on_edge;
  for (int t = 0; t < count; ++t) {
    if (side[t] == 0) continue;
    for (int k = 0; k < 3; ++k) {
      int a = shell.triangles[t][k], b = shell.triangles[t][(k + 1) % 3];
      if (a > b) std::swap(a, b);
      const auto [it, inserted] = first_on_edge.emplace(std::make_pair(a, b), t);
      if (!inserted && side[it->second] == side[t]) parent[Find(parent, t)] = Find(parent, it->second);
    }
  }
  std::map<int, int> feature_of_root;  // in the order of each feature's first triangle
  std::vector<std::vector<int>> features;
  std::vector<int> feature_side;
  for (int t = 0; t < count; ++t) {
    if (side[t] == 0) continue;
    const auto [it, inserted] = feature_of_root.emplace(Find(parent, t), static_cast<int>(features.size()));
    if (inserted) {
      features.emplace_back();
      feature_side.push_back(side[t]);
    }
    features[it->second].push_back(t);
  }
  if (features.empty()) {
    out.reason = "a plate with nothing standing out of it";
    return out;
  }

  // 3. Boxes, merged until none overlaps another.
  const auto box_of = [&](std::size_t f) {
    const double face = feature_side[f] > 0 ? out.high - eps : out.low + eps;
    return FeatureBox(shell, features[f], n, feature_side[f], face, margin);
  };
  std::vector<TurnedBox> boxes;
  for (std::size_t f = 0; f < features.size(); ++f) boxes.push_back(box_of(f));
  for (bool merged = true; merged;) {
    merged = false;
    for (std::size_t i = 0; i < features.size() && !merged; ++i) {
      for (std::size_t j = i + 1; j < features.size() && !merged; ++j) {
        if (feature_side[i] != feature_side[j] || !Overlap(boxes[i], boxes[j])) continue;
        features[i].insert(features[i].end(), features[j].begin(), features[j].end());
        std::sort(features[i].begin(), features[i].end());
        features.erase(features.begin() + j);
        feature_side.erase(feature_side.begin() + j);
        boxes.erase(boxes.begin() + j);
        boxes[i] = box_of(i);
        merged = true;
      }
    }
  }
  for (std::size_t f = 0; f < features.size(); ++f) {
    Protrusion p;
    p.triangles = std::move(features[f]);
    p.box = boxes[f];
    p.side = feature_side[f];
    p.volume = FeatureVolume(shell, p.triangles, (p.side > 0 ? out.high : out.low) * n);
    out.features.push_back(std::move(p));
  }
  out.found = true;
  out.reason = Fmt("a plate %.3g thick with %zu features standing out of it", thickness, out.features.size());
  return out;
}

}  // namespace ausbau
