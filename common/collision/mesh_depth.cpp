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

double SegmentDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d d = b - a;
  const double length_squared = d.squaredNorm();
  const double u = length_squared > 0 ? std::clamp((p - a).dot(d) / length_squared, 0.0, 1.0) : 0.0;
  return (a + u * d - p).norm();
}

// Whether triangles p and q are more than `gap` apart along some axis
// (then they do not touch). Axes: both normals, the nine edge-edge cross
// products and each triangle's in-plane edge normals (coplanar pairs): for
// two triangles, disjoint means some such axis separates them. False may
// also mean only that the gap is smaller than asked (the caller refines).
bool TrianglesApart(const std::array<Eigen::Vector3d, 3>& p, const std::array<Eigen::Vector3d, 3>& q, double gap) {
  const Eigen::Vector3d o = q[0];  // rounding scales with the triangles, not their place
  const Eigen::Vector3d a[3] = {p[0] - o, p[1] - o, p[2] - o};
  const Eigen::Vector3d b[3] = {Eigen::Vector3d::Zero(), q[1] - o, q[2] - o};
  const Eigen::Vector3d ea[3] = {a[1] - a[0], a[2] - a[1], a[0] - a[2]};
  const Eigen::Vector3d eb[3] = {b[1] - b[0], b[2] - b[1], b[0] - b[2]};
  const auto apart = [&](const Eigen::Vector3d& axis) {
    const double length = axis.norm();
    if (!(length > 0) || !std::isfinite(length)) return false;
    const Eigen::Vector3d u = axis / length;
    double a_lo = u.dot(a[0]), a_hi = a_lo, b_lo = 0, b_hi = 0;
    for (int k = 1; k < 3; ++k) {
      a_lo = std::min(a_lo, u.dot(a[k])), a_hi = std::max(a_hi, u.dot(a[k]));
      b_lo = std::min(b_lo, u.dot(b[k])), b_hi = std::max(b_hi, u.dot(b[k]));
    }
    return a_hi + gap < b_lo || b_hi + gap < a_lo;
  };
  const Eigen::Vector3d na = ea[0].cross(ea[1]), nb = eb[0].cross(eb[1]);
  if (apart(na) || apart(nb)) return true;
  for (const auto& x : ea)
    for (const auto& y : eb)
      if (apart(x.cross(y))) return true;
  for (int k = 0; k < 3; ++k)
    if (apart(na.cross(ea[k])) || apart(nb.cross(eb[k]))) return true;
  return false;
}

// Whether the prism of triangle p swept along w (the convex hull of p and
// p + w) and triangle q are more than `gap` apart along some axis. Axes:
// the face normals of both (the prism's ends and sides; each flat shape's
// in-plane edge normals, for a flat prism or coplanar triangles) and the
// cross products of their edge directions: for two convex polytopes,
// disjoint means some such axis separates them.
bool PrismApartFromTriangle(const std::array<Eigen::Vector3d, 3>& p, const Eigen::Vector3d& w,
                            const std::array<Eigen::Vector3d, 3>& q, double gap) {
  const Eigen::Vector3d o = q[0];
  Eigen::Vector3d a[6];
  for (int k = 0; k < 3; ++k) {
    a[k] = p[k] - o;
    a[k + 3] = a[k] + w;
  }
  const Eigen::Vector3d b[3] = {Eigen::Vector3d::Zero(), q[1] - o, q[2] - o};
  const Eigen::Vector3d ea[4] = {a[1] - a[0], a[2] - a[1], a[0] - a[2], w};
  const Eigen::Vector3d eb[3] = {b[1] - b[0], b[2] - b[1], b[0] - b[2]};
  const auto apart = [&](const Eigen::Vector3d& axis) {
    const double length = axis.norm();
    if (!(length > 0) || !std::isfinite(length)) return false;
    const Eigen::Vector3d u = axis / length;
    double a_lo = u.dot(a[0]), a_hi = a_lo, b_lo = 0, b_hi = 0;
    for (int k = 1; k < 6; ++k) a_lo = std::min(a_lo, u.dot(a[k])), a_hi = std::max(a_hi, u.dot(a[k]));
    for (int k = 1; k < 3; ++k) b_lo = std::min(b_lo, u.dot(b[k])), b_hi = std::max(b_hi, u.dot(b[k]));
    return a_hi + gap < b_lo || b_hi + gap < a_lo;
  };
  const Eigen::Vector3d na = ea[0].cross(ea[1]), nb = eb[0].cross(eb[1]);
  if (apart(na) || apart(nb)) return true;
  for (int k = 0; k < 3; ++k)
    if (apart(ea[k].cross(w))) return true;
  for (const auto& x : ea)
    for (const auto& y : eb)
      if (apart(x.cross(y))) return true;
  for (int k = 0; k < 3; ++k)
    if (apart(na.cross(ea[k])) || apart(nb.cross(eb[k]))) return true;
  return apart(na.cross(w));
}

// A convex polytope given by its corners, the normals of its faces and the
// directions of its edges (what a separating axis test needs of it).
struct ConvexPiece {
  std::vector<Eigen::Vector3d> corners, face_normals, edges;
};

// Whether convex piece a and triangle q are more than `gap` apart along one
// of the axes a separating axis test tries for them (face normals, the
// cross products of edge directions, in-plane edge normals of q): false may
// also mean only that the gap is smaller than asked.
bool PieceApartFromTriangle(const ConvexPiece& a, const std::array<Eigen::Vector3d, 3>& q, double gap) {
  const Eigen::Vector3d o = q[0];
  const Eigen::Vector3d b[3] = {Eigen::Vector3d::Zero(), q[1] - o, q[2] - o};
  const Eigen::Vector3d eb[3] = {b[1] - b[0], b[2] - b[1], b[0] - b[2]};
  const auto apart = [&](const Eigen::Vector3d& axis) {
    const double length = axis.norm();
    if (!(length > 0) || !std::isfinite(length)) return false;
    const Eigen::Vector3d u = axis / length;
    double a_lo = std::numeric_limits<double>::infinity(), a_hi = -a_lo, b_lo = 0, b_hi = 0;
    for (const auto& c : a.corners) {
      const double x = u.dot(c - o);
      a_lo = std::min(a_lo, x), a_hi = std::max(a_hi, x);
    }
    for (int k = 1; k < 3; ++k) b_lo = std::min(b_lo, u.dot(b[k])), b_hi = std::max(b_hi, u.dot(b[k]));
    return a_hi + gap < b_lo || b_hi + gap < a_lo;
  };
  const Eigen::Vector3d nb = eb[0].cross(eb[1]);
  if (apart(nb)) return true;
  for (const auto& n : a.face_normals)
    if (apart(n)) return true;
  for (const auto& x : a.edges)
    for (const auto& y : eb)
      if (apart(x.cross(y))) return true;
  for (const auto& y : eb)
    if (apart(nb.cross(y))) return true;
  return false;
}

// The prism of triangle t swept along w (the convex hull of t and t + w)
// cut by a plane (normal . x = offset): its part in front (normal . x >
// offset) and its part behind, each as a convex piece, and the points where
// its edges cross the plane.
struct PrismSplit {
  ConvexPiece front, behind;
  std::vector<Eigen::Vector3d> cut;
};
PrismSplit SplitPrismAtPlane(const std::array<Eigen::Vector3d, 3>& t, const Eigen::Vector3d& w,
                             const Eigen::Vector3d& normal, double offset) {
  const Eigen::Vector3d c[6] = {t[0], t[1], t[2], t[0] + w, t[1] + w, t[2] + w};
  double h[6];
  PrismSplit split;
  for (int k = 0; k < 6; ++k) {
    h[k] = normal.dot(c[k]) - offset;
    (h[k] > 0 ? split.front : split.behind).corners.push_back(c[k]);
  }
  static constexpr int kEdges[9][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 4}, {4, 5}, {5, 3}, {0, 3}, {1, 4}, {2, 5}};
  for (const auto& e : kEdges) {
    const int i = e[0], j = e[1];
    if ((h[i] > 0) == (h[j] > 0)) continue;
    const Eigen::Vector3d p = c[i] + (h[i] / (h[i] - h[j])) * (c[j] - c[i]);
    split.cut.push_back(p);
    split.front.corners.push_back(p);
    split.behind.corners.push_back(p);
  }
  // Faces: the prism's ends and sides, and the plane; edges: the prism's
  // and where its faces meet the plane.
  const Eigen::Vector3d e[3] = {t[1] - t[0], t[2] - t[1], t[0] - t[2]};
  const Eigen::Vector3d n = e[0].cross(e[1]);
  std::vector<Eigen::Vector3d> faces = {n, e[0].cross(w), e[1].cross(w), e[2].cross(w), normal};
  std::vector<Eigen::Vector3d> edges = {e[0], e[1], e[2], w, n.cross(e[0]), n.cross(e[1]), n.cross(e[2]), n.cross(w)};
  for (int k = 0; k < 4; ++k) edges.push_back(normal.cross(faces[k]));
  split.front.face_normals = split.behind.face_normals = faces;
  split.front.edges = split.behind.edges = edges;
  return split;
}

}  // namespace

bool DepthSurface::MayMeet(const std::array<Eigen::Vector3d, 3>& t, double gap) const {
  return MayMeetOutside({t[0], t[1], t[2]}, gap, nullptr, -1);
}

namespace {

// The triangles on each edge (as the pair of its vertices, smaller first).
using TrianglesByEdge = std::map<std::pair<int, int>, std::vector<int>>;
std::pair<int, int> EdgeKey(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

TrianglesByEdge TrianglesOfEdges(const std::vector<std::array<int, 3>>& triangles) {
  TrianglesByEdge by_edge;
  for (int t = 0; t < static_cast<int>(triangles.size()); ++t)
    for (int k = 0; k < 3; ++k) by_edge[EdgeKey(triangles[t][k], triangles[t][(k + 1) % 3])].push_back(t);
  return by_edge;
}

// The triangles reached from `seed` through shared edges, stepping only onto
// those `joins` accepts and not yet `seen` (marked as they are reached).
template <typename Joins>
std::vector<int> GrowThroughEdges(int seed, const std::vector<std::array<int, 3>>& triangles,
                                  const TrianglesByEdge& by_edge, std::vector<bool>* seen, Joins joins) {
  std::vector<int> members, open = {seed};
  (*seen)[seed] = true;
  while (!open.empty()) {
    const int t = open.back();
    open.pop_back();
    members.push_back(t);
    for (int k = 0; k < 3; ++k) {
      for (int u : by_edge.at(EdgeKey(triangles[t][k], triangles[t][(k + 1) % 3]))) {
        if ((*seen)[u] || !joins(u)) continue;
        (*seen)[u] = true;
        open.push_back(u);
      }
    }
  }
  return members;
}

// How many of `members` use each of their edges (1: a boundary edge).
std::map<std::pair<int, int>, int> EdgeUses(const std::vector<std::array<int, 3>>& triangles,
                                            const std::vector<int>& members) {
  std::map<std::pair<int, int>, int> uses;
  for (int t : members)
    for (int k = 0; k < 3; ++k) ++uses[EdgeKey(triangles[t][k], triangles[t][(k + 1) % 3])];
  return uses;
}

// The convex planar patches (mesh_depth.h): regions of coplanar triangles
// connected through shared edges; a region whose boundary leaves every one
// of its vertices on its inner side is a convex polygon, kept as its plane
// and boundary edges (at most kMaxPatchEdges).
void BuildConvexPlanarPatches(const std::vector<Eigen::Vector3d>& vertices,
                              const std::vector<std::array<int, 3>>& triangles, const TrianglesByEdge& by_edge,
                              int max_edges, std::vector<DepthSurface::Patch>* patches, std::vector<int>* patch_of) {
  const int n = static_cast<int>(triangles.size());
  patch_of->assign(n, -1);
  std::vector<Eigen::Vector3d> normal(n, Eigen::Vector3d::Zero());
  Aabb box;
  for (const auto& v : vertices) box.Extend(v);
  const double flat = 1e-9 * std::max(1.0, box.Diagonal());
  for (int t = 0; t < n; ++t) {
    const auto& tri = triangles[t];
    const Eigen::Vector3d cross = (vertices[tri[1]] - vertices[tri[0]]).cross(vertices[tri[2]] - vertices[tri[0]]);
    if (cross.norm() > 0) normal[t] = cross.normalized();
  }
  std::vector<bool> seen(n, false);
  for (int seed = 0; seed < n; ++seed) {
    if (seen[seed] || normal[seed].isZero()) continue;
    const Eigen::Vector3d nn = normal[seed];
    const Eigen::Vector3d origin = vertices[triangles[seed][0]];
    const std::vector<int> members = GrowThroughEdges(seed, triangles, by_edge, &seen, [&](int u) {
      if (normal[u].dot(nn) < 1 - 1e-12) return false;
      for (int v : triangles[u])
        if (!(std::abs((vertices[v] - origin).dot(nn)) <= flat)) return false;
      return true;
    });
    if (members.size() < 2) continue;
    std::map<std::pair<int, int>, int> uses = EdgeUses(triangles, members);
    // A region with more boundary edges than a patch may have is no patch:
    // not checked for convexity, which costs its edges times its vertices
    // (a cylinder's facet, one coplanar strip of 1,600 triangles along a
    // tube of 600 mm, took seconds a shell).
    int boundary = 0;
    for (const auto& [edge, count] : uses)
      boundary += count == 1 && nn.cross(vertices[edge.second] - vertices[edge.first]).norm() != 0;
    if (boundary > max_edges) continue;
    DepthSurface::Patch patch;
    patch.normal = nn;
    patch.origin = origin;
    bool convex = true;
    for (int t : members) {
      for (int k = 0; k < 3 && convex; ++k) {
        const int a = triangles[t][k], b = triangles[t][(k + 1) % 3], c = triangles[t][(k + 2) % 3];
        if (uses[{std::min(a, b), std::max(a, b)}] != 1) continue;
        Eigen::Vector3d inward = nn.cross(vertices[b] - vertices[a]);
        if (inward.norm() == 0) continue;
        inward.normalize();
        if ((vertices[c] - vertices[a]).dot(inward) < 0) inward = -inward;
        for (int m : members)
          for (int v : triangles[m]) convex = convex && (vertices[v] - vertices[a]).dot(inward) >= -flat;
        patch.edge_a.push_back(vertices[a]);
        patch.edge_b.push_back(vertices[b]);
        patch.inward.push_back(inward);
      }
    }
    if (!convex || static_cast<int>(patch.edge_a.size()) > max_edges) continue;
    for (int t : members) (*patch_of)[t] = static_cast<int>(patches->size());
    patches->push_back(std::move(patch));
  }
}

}  // namespace

DepthSurface::DepthSurface(const Shell& shell)
    : vertices_(shell.vertices), triangles_(shell.triangles), bvh_(shell.vertices, shell.triangles) {
  for (const auto& v : vertices_) box_.Extend(v);
  flat_ = 1e-9 * std::max(1.0, box_.Diagonal());
  const int n = static_cast<int>(triangles_.size());
  const TrianglesByEdge by_edge = TrianglesOfEdges(triangles_);
  BuildConvexPlanarPatches(vertices_, triangles_, by_edge, kMaxPatchEdges, &patches_, &patch_of_);
  // Consistently oriented: every directed edge once, its reverse once.
  std::map<std::pair<int, int>, int> directed;
  for (const auto& tri : triangles_)
    for (int e = 0; e < 3; ++e) ++directed[{tri[e], tri[(e + 1) % 3]}];
  oriented_ = shell.closed && !directed.empty();
  for (const auto& [edge, count] : directed) {
    const auto reverse = directed.find({edge.second, edge.first});
    if (count != 1 || reverse == directed.end() || reverse->second != 1) oriented_ = false;
  }
  if (!oriented_) {
    solid_ = GapShare(directed) <= kMaxGapShare;
    // Inside by the winding number: by the hierarchy, where each query
    // summed every triangle (an open or cut shell of 110,000 triangles:
    // 3 ms a query, 93% of a plan of CAx-IF's s1 with S cropped to D's
    // reach).
    if (solid_) winding_ = std::make_shared<const WindingBvh>(TriangleMesh{vertices_, triangles_});
    if (solid_ && shell.complete_within) InsideByNormalWithinCrop(directed, *shell.complete_within);
    return;
  }
  double signed_volume = 0;
  const Eigen::Vector3d c = box_.Center();
  for (const auto& tri : triangles_)
    signed_volume += (vertices_[tri[0]] - c).dot((vertices_[tri[1]] - c).cross(vertices_[tri[2]] - c));
  outward_ = signed_volume < 0 ? -1.0 : 1.0;
  convex_ = shell.convex;
  BuildPseudoNormals();
  BuildFaceRegions(by_edge);
  // A convex shell's face planes (coplanar triangles once), when few.
  if (convex_) {
    for (int t = 0; t < n && static_cast<int>(planes_.size()) <= kMaxConvexPlanes; ++t) {
      const Eigen::Vector3d& normal = face_normal_[t];
      if (normal.squaredNorm() == 0) continue;
      const double offset = normal.dot(vertices_[triangles_[t][0]]);
      const bool seen = std::any_of(planes_.begin(), planes_.end(), [&](const auto& plane) {
        return plane.first.dot(normal) >= 1 - 1e-12 && std::abs(plane.second - offset) <= 1e-9 * box_.Diagonal();
      });
      if (!seen) planes_.emplace_back(normal, offset);
    }
    if (static_cast<int>(planes_.size()) > kMaxConvexPlanes) planes_.clear();
  }
}

void DepthSurface::BuildPseudoNormals() {
  const int n = static_cast<int>(triangles_.size());
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
    face_normal_[t] = norm > 0 ? Eigen::Vector3d(outward_ * cross / norm) : Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      const int i = tri[k], j = tri[(k + 1) % 3], l = tri[(k + 2) % 3];
      vertex_normal_[i] += AngleAt(vertices_[i], vertices_[j], vertices_[l]) * face_normal_[t];
      // (Eigen's default constructor leaves a vector uninitialized.)
      edge_sum.try_emplace({std::min(j, l), std::max(j, l)}, Eigen::Vector3d::Zero()).first->second += face_normal_[t];
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

void DepthSurface::InsideByNormalWithinCrop(const std::map<std::pair<int, int>, int>& directed, const Aabb& box) {
  // Consistently oriented, and open only where the crop cut it: every
  // boundary edge (one without its reverse) lies outside the box, as the
  // triangles the crop dropped do.
  for (const auto& [edge, count] : directed) {
    if (count != 1) return;
    const auto reverse = directed.find({edge.second, edge.first});
    if (reverse != directed.end()) {
      if (reverse->second != 1) return;
      continue;
    }
    Aabb segment;
    segment.Extend(vertices_[edge.first]);
    segment.Extend(vertices_[edge.second]);
    if (!segment.SeparatedFrom(box)) return;
  }
  // Which side is inside: the winding number's answer just off triangles
  // spread over the shell, where it decides clearly (each triangle's two
  // sides differ by one winding). Every decided sample must agree.
  constexpr int kSamples = 16;
  const int n = static_cast<int>(triangles_.size());
  int outward = 0, inward = 0;
  for (int i = 0; i < kSamples && i < n; ++i) {
    const auto& tri = triangles_[static_cast<std::size_t>(i) * n / std::min(n, kSamples)];
    const Eigen::Vector3d& a = vertices_[tri[0]];
    const Eigen::Vector3d& b = vertices_[tri[1]];
    const Eigen::Vector3d& c = vertices_[tri[2]];
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    const double shortest = std::min({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    if (!(cross.norm() > 0) || !(shortest > 0)) continue;
    const Eigen::Vector3d centre = (a + b + c) / 3.0, off = 1e-3 * shortest * cross.normalized();
    const bool front = winding_->AbsoluteWindingExceeds(centre + off, 0.5);
    const bool back = winding_->AbsoluteWindingExceeds(centre - off, 0.5);
    if (back && !front) ++outward;  // the corner order's normal points out
    if (front && !back) ++inward;
  }
  if ((outward > 0) == (inward > 0)) return;  // none decided, or they disagree
  outward_ = outward > 0 ? 1.0 : -1.0;
  BuildPseudoNormals();
  complete_within_ = box;
}

// The boundary loops' area (each loop filled: the norm of its vector area,
// 0 for a crack between two unwelded faces) over the shell's area.
double DepthSurface::GapShare(const std::map<std::pair<int, int>, int>& directed) const {
  // Boundary edges: those whose reverse (and which themselves) occur once
  // in all; chained by their start vertex.
  std::multimap<int, int> next;
  for (const auto& [edge, count] : directed) {
    const auto reverse = directed.find({edge.second, edge.first});
    if (count == 1 && reverse == directed.end()) next.emplace(edge.first, edge.second);
  }
  double surface = 0;
  for (const auto& tri : triangles_)
    surface += 0.5 * (vertices_[tri[1]] - vertices_[tri[0]]).cross(vertices_[tri[2]] - vertices_[tri[0]]).norm();
  if (next.empty()) return 0;
  if (!(surface > 0)) return std::numeric_limits<double>::infinity();
  double gaps = 0;
  while (!next.empty()) {
    const int first = next.begin()->first;
    const Eigen::Vector3d& origin = vertices_[first];
    Eigen::Vector3d vector_area = Eigen::Vector3d::Zero();
    int at = first;
    for (auto it = next.find(at); it != next.end(); it = next.find(at)) {
      const int to = it->second;
      next.erase(it);
      vector_area += 0.5 * (vertices_[at] - origin).cross(vertices_[to] - origin);
      at = to;
      if (at == first) break;
    }
    gaps += vector_area.norm();
  }
  return gaps / surface;
}

double DepthSurface::PatchDistance(const Eigen::Vector3d& p, int triangle) const {
  const int index = patch_of_[triangle];
  if (index < 0) {
    const auto& f = triangles_[triangle];
    return (ClosestPointOnTriangle(p, vertices_[f[0]], vertices_[f[1]], vertices_[f[2]], kDegenerate, kWeights) - p)
        .norm();
  }
  // The distance to a convex polygon: to its plane where p projects inside,
  // else to its nearest boundary edge.
  const Patch& patch = patches_[index];
  const double height = (p - patch.origin).dot(patch.normal);
  const Eigen::Vector3d q = p - height * patch.normal;
  bool inside = true;
  for (std::size_t e = 0; e < patch.edge_a.size() && inside; ++e)
    inside = (q - patch.edge_a[e]).dot(patch.inward[e]) >= 0;
  if (inside) return std::abs(height);
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t e = 0; e < patch.edge_a.size(); ++e)
    best = std::min(best, SegmentDistance(p, patch.edge_a[e], patch.edge_b[e]));
  return best;
}

// The flat regions (mesh_depth.h FaceRegion): triangles joined through
// edges whose outward normals are within kFlatCos of the first one's (the
// largest triangle left first); each region's plane is its area-weighted
// normal through the mean of its corners, and `deviation` how far any
// corner lies off it, as measured (rounding: a CAD face written in float32
// far from the origin is flat to some 1e-5 of its coordinates only).
void DepthSurface::BuildFaceRegions(const TrianglesByEdge& by_edge) {
  constexpr double kFlatCos = 1 - 1e-6;  // about 1.4 mrad
  const int n = static_cast<int>(triangles_.size());
  region_of_.assign(n, -1);
  std::vector<double> area(n, 0);
  for (int t = 0; t < n; ++t) {
    const auto& f = triangles_[t];
    area[t] = 0.5 * (vertices_[f[1]] - vertices_[f[0]]).cross(vertices_[f[2]] - vertices_[f[0]]).norm();
  }
  std::vector<int> order(n);
  for (int t = 0; t < n; ++t) order[t] = t;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return area[a] > area[b]; });
  std::vector<bool> seen(n, false);
  for (int seed : order) {
    if (seen[seed] || face_normal_[seed].squaredNorm() == 0) continue;
    const std::vector<int> members = GrowThroughEdges(
        seed, triangles_, by_edge, &seen, [&](int u) { return face_normal_[u].dot(face_normal_[seed]) >= kFlatCos; });
    FaceRegion region;
    Eigen::Vector3d weighted = Eigen::Vector3d::Zero();
    for (int t : members) weighted += area[t] * face_normal_[t];
    if (!(weighted.norm() > 0)) continue;
    region.normal = weighted.normalized();
    std::map<int, int> corners;  // vertex -> use
    for (int t : members)
      for (int v : triangles_[t]) ++corners[v];
    region.origin = Eigen::Vector3d::Zero();
    for (const auto& [v, uses] : corners) region.origin += vertices_[v];
    region.origin /= static_cast<double>(corners.size());
    for (const auto& [v, uses] : corners)
      region.deviation = std::max(region.deviation, std::abs((vertices_[v] - region.origin).dot(region.normal)));
    region.u = region.normal.unitOrthogonal();
    region.v = region.normal.cross(region.u);
    for (const auto& [edge, count] : EdgeUses(triangles_, members)) {
      if (count != 1) continue;
      region.edge_a.push_back(region.InPlane(vertices_[edge.first]));
      region.edge_b.push_back(region.InPlane(vertices_[edge.second]));
    }
    for (int t : members) region_of_[t] = static_cast<int>(regions_.size());
    regions_.push_back(std::move(region));
  }
}

namespace {
// Whether segment (a, b) and triangle t of a plane (either may be
// degenerate) are more than `gap` apart along an edge normal of one of them.
bool SegmentApartFromTriangle(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d (&t)[3],
                              double gap) {
  const auto apart = [&](const Eigen::Vector2d& direction) {
    const double length = direction.norm();
    if (!(length > 0)) return false;
    const Eigen::Vector2d axis = Eigen::Vector2d(-direction.y(), direction.x()) / length;
    const double sa = axis.dot(a), sb = axis.dot(b);
    double t_lo = axis.dot(t[0]), t_hi = t_lo;
    for (int k = 1; k < 3; ++k) t_lo = std::min(t_lo, axis.dot(t[k])), t_hi = std::max(t_hi, axis.dot(t[k]));
    return std::max(sa, sb) + gap < t_lo || t_hi + gap < std::min(sa, sb);
  };
  if (apart(b - a)) return true;
  for (int k = 0; k < 3; ++k)
    if (apart(t[(k + 1) % 3] - t[k])) return true;
  return false;
}
}  // namespace

namespace {
// Triangle t cut by a plane, given each corner's height above it: the
// corners of the part behind (height <= 0) and of the part in front, in
// order round each, and the points where its edges cross the plane.
struct PlaneSplit {
  std::vector<Eigen::Vector3d> behind, front, cut;
};
PlaneSplit SplitAtPlane(const std::array<Eigen::Vector3d, 3>& t, const double (&height)[3]) {
  PlaneSplit split;
  for (int k = 0; k < 3; ++k) {
    const int j = (k + 1) % 3;
    (height[k] > 0 ? split.front : split.behind).push_back(t[k]);
    if ((height[k] > 0) != (height[j] > 0)) {
      const Eigen::Vector3d p = t[k] + (height[k] / (height[k] - height[j])) * (t[j] - t[k]);
      split.cut.push_back(p);
      split.front.push_back(p);
      split.behind.push_back(p);
    }
  }
  return split;
}
}  // namespace

double DepthSurface::FaceRegionBound(const std::array<Eigen::Vector3d, 3>& t, int face, double gap,
                                     double below) const {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  if (face < 0 || region_of_.empty() || region_of_[face] < 0) return kNone;
  const FaceRegion& region = regions_[region_of_[face]];
  // Heights above the region's plane raised by its deviation (and a
  // rounding margin): its triangles lie wholly behind the raised plane.
  const double raise = region.deviation + 2 * flat_;
  double height[3], bound = 0;
  int front = 0;
  for (int k = 0; k < 3; ++k) {
    height[k] = (t[k] - region.origin).dot(region.normal) - raise;
    if (height[k] > 0) {
      ++front;
    } else {
      bound = std::max(bound, -height[k]);
    }
  }
  if (front == 3 || std::max(bound, raise + region.deviation) >= below) return kNone;
  // t's shadow on the plane lies in the region: the centre's shadow in
  // `face`, and no boundary edge of the region near the shadow.
  Eigen::Vector2d shadow[3];
  for (int k = 0; k < 3; ++k) shadow[k] = region.InPlane(t[k]);
  const Eigen::Vector2d centre = (shadow[0] + shadow[1] + shadow[2]) / 3.0;
  const auto& f = triangles_[face];
  const Eigen::Vector2d corner[3] = {region.InPlane(vertices_[f[0]]), region.InPlane(vertices_[f[1]]),
                                     region.InPlane(vertices_[f[2]])};
  const auto cross = [](const Eigen::Vector2d& x, const Eigen::Vector2d& y) { return x.x() * y.y() - x.y() * y.x(); };
  const double twice_area = cross(corner[1] - corner[0], corner[2] - corner[0]);
  for (int k = 0; k < 3; ++k)
    if (!(cross(corner[(k + 1) % 3] - corner[k], centre - corner[k]) * twice_area >= 0)) return kNone;
  const Eigen::Vector2d lo = shadow[0].cwiseMin(shadow[1]).cwiseMin(shadow[2]).array() - gap;
  const Eigen::Vector2d hi = shadow[0].cwiseMax(shadow[1]).cwiseMax(shadow[2]).array() + gap;
  for (std::size_t e = 0; e < region.edge_a.size(); ++e) {
    const Eigen::Vector2d& a = region.edge_a[e];
    const Eigen::Vector2d& b = region.edge_b[e];
    if (std::max(a.x(), b.x()) < lo.x() || std::min(a.x(), b.x()) > hi.x() || std::max(a.y(), b.y()) < lo.y() ||
        std::min(a.y(), b.y()) > hi.y())
      continue;
    if (!SegmentApartFromTriangle(a, b, shadow, gap)) return kNone;
  }
  // The part in front, a triangle or a quadrilateral.
  if (front > 0 && MayMeetOutside(SplitAtPlane(t, height).front, gap, &region_of_, face)) return kNone;
  // A point behind the raised plane and over the region is at most its
  // height below the plane, plus the deviation, from the surface point on
  // the same normal line: at most `bound`, or raise + deviation for a point
  // within the raise.
  return std::max(bound, raise + region.deviation);
}

bool DepthSurface::InsidePatch(const Eigen::Vector3d& p, int triangle, double margin) const {
  const int index = patch_of_[triangle];
  if (index >= 0) {
    const Patch& patch = patches_[index];
    const Eigen::Vector3d q = p - (p - patch.origin).dot(patch.normal) * patch.normal;
    for (std::size_t e = 0; e < patch.edge_a.size(); ++e)
      if (!((q - patch.edge_a[e]).dot(patch.inward[e]) > margin)) return false;
    return true;
  }
  const auto& f = triangles_[triangle];
  const Eigen::Vector3d& normal = face_normal_[triangle];
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d& a = vertices_[f[k]];
    const Eigen::Vector3d& b = vertices_[f[(k + 1) % 3]];
    const Eigen::Vector3d& c = vertices_[f[(k + 2) % 3]];
    Eigen::Vector3d inward = normal.cross(b - a);
    if (!(inward.norm() > 0)) return false;
    inward.normalize();
    if ((c - a).dot(inward) < 0) inward = -inward;
    if (!((p - a).dot(inward) > margin)) return false;
  }
  return true;
}

bool DepthSurface::MayMeetOutside(const std::vector<Eigen::Vector3d>& polygon, double gap,
                                  const std::vector<int>* group_of, int triangle) const {
  const int group = group_of ? (*group_of)[triangle] : -1;
  // Fanned from its first corner (a convex polygon, corners in order).
  for (std::size_t m = 1; m + 1 < polygon.size(); ++m) {
    const std::array<Eigen::Vector3d, 3> t = {polygon[0], polygon[m], polygon[m + 1]};
    const Eigen::Vector3d lo = t[0].cwiseMin(t[1]).cwiseMin(t[2]).array() - gap;
    const Eigen::Vector3d hi = t[0].cwiseMax(t[1]).cwiseMax(t[2]).array() + gap;
    bool meets = false;
    bvh_.ForEachTriangleNear(lo, hi, [&](int k) {
      if (k == triangle || (group >= 0 && (*group_of)[k] == group)) return true;
      const auto& f = triangles_[k];
      meets = !TrianglesApart(t, {vertices_[f[0]], vertices_[f[1]], vertices_[f[2]]}, gap);
      return !meets;
    });
    if (meets) return true;
  }
  return false;
}

double DepthSurface::StraddleBound(const std::array<Eigen::Vector3d, 3>& t, int face, double gap) const {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  if (!oriented_ || face < 0) return kNone;
  const Eigen::Vector3d& normal = face_normal_[face];  // outward
  if (normal.squaredNorm() == 0) return kNone;
  // The plane is raised by twice the patch's flatness, so P's triangles lie
  // wholly behind it; the slab between belongs to the part behind, whose
  // bound holds for any point.
  const int index = patch_of_[face];
  const Eigen::Vector3d origin = index >= 0 ? patches_[index].origin : vertices_[triangles_[face][0]];
  const double raise = 2 * flat_;
  double height[3];
  int front = 0;
  for (int k = 0; k < 3; ++k) {
    height[k] = (t[k] - origin).dot(normal) - raise;
    if (height[k] > 0) ++front;
  }
  if (front == 0 || front == 3) return kNone;
  const PlaneSplit split = SplitAtPlane(t, height);
  if (split.cut.size() != 2 || !InsidePatch(0.5 * (split.cut[0] + split.cut[1]), face, raise)) return kNone;
  // The part in front, a triangle or a quadrilateral.
  if (MayMeetOutside(split.front, gap, &patch_of_, face)) return kNone;
  double bound = 0;
  for (const auto& c : split.behind) bound = std::max(bound, PatchDistance(c, face));
  return bound;
}

bool DepthSurface::Inside(const Eigen::Vector3d& p, const TriangleBvh::Nearest& nearest) const {
  if (nearest.triangle < 0 || nearest.distance_squared == 0 || !solid_) return false;
  if (!oriented_) {
    // A shell the crop cut: where its nearest point is nearer than the
    // crop's edge, every triangle the crop dropped is farther, so the
    // nearest point is the whole shell's, and its pseudo-normal decides as
    // for a closed shell. (The winding number of the cut shell alone cost
    // most of every stage on CAx-IF's s1.)
    if (complete_within_) {
      const Aabb& box = *complete_within_;
      const double slack = std::min((p - box.min).minCoeff(), (box.max - p).minCoeff());
      if (slack > 0 && nearest.distance_squared < slack * slack)
        return (p - nearest.point).dot(NormalAtNearest(p, nearest)) < 0;
    }
    return winding_->AbsoluteWindingExceeds(p, 0.5);
  }
  return (p - nearest.point).dot(NormalAtNearest(p, nearest)) < 0;
}

Eigen::Vector3d DepthSurface::NormalAtNearest(const Eigen::Vector3d& p, const TriangleBvh::Nearest& nearest) const {
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
  if (zeros >= 2 && one >= 0) return vertex_normal_[tri[one]];
  if (zeros == 1) return edge_normal_[nearest.triangle][zero];
  return face_normal_[nearest.triangle];
}

double DepthSurface::ShiftOffBound(const std::array<Eigen::Vector3d, 3>& t, const TriangleBvh::Nearest& nearest,
                                   double shift, double gap, const Eigen::Vector3d& into_own_shell,
                                   bool corner_directions) const {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  if (!oriented_ || !solid_ || nearest.triangle < 0 || !(shift > gap)) return kNone;
  const Eigen::Vector3d centre = (t[0] + t[1] + t[2]) / 3.0;
  // A centre deeper than the move stays inside whichever way it moves.
  if (nearest.distance_squared > shift * shift && Inside(centre, nearest)) return kNone;
  const auto frees = [&](const Eigen::Vector3d& direction) {
    const double length = direction.norm();
    if (!(length > 0)) return false;
    const Eigen::Vector3d move = (shift / length) * direction;
    const std::array<Eigen::Vector3d, 3> moved = {t[0] + move, t[1] + move, t[2] + move};
    const Eigen::Vector3d moved_centre = centre + move;
    return !Inside(moved_centre, bvh_.NearestPoint(moved_centre, nearest.triangle)) && !MayMeet(moved, gap);
  };
  const Eigen::Vector3d face = face_normal_[nearest.triangle], at_centre = NormalAtNearest(centre, nearest);
  if (frees(into_own_shell) || frees(face) || (!at_centre.isApprox(face) && frees(at_centre))) return shift;
  if (!corner_directions || into_own_shell.isZero(0)) return kNone;
  // Into its own shell and off this one's surface at a corner at once: a
  // plate's face around a bore, under a bolt's head, moved into the plate
  // still meets the shank (its polygon reaches past the bore's), and moved
  // off the head still meets the head; halfway between the plate's inward
  // normal and the normal at the corner on the rim (the edge between head
  // and shank) it leaves both.
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d normal = NormalAtNearest(t[k], bvh_.NearestPoint(t[k], nearest.triangle));
    const double length = normal.norm();
    if (!(length > 0) || normal.isApprox(face) || normal.isApprox(at_centre)) continue;
    if (frees(into_own_shell.normalized() + normal / length)) return shift;
  }
  return kNone;
}

double DepthSurface::SignedDistance(const Eigen::Vector3d& p, int* triangle) const {
  const TriangleBvh::Nearest nearest = bvh_.NearestPoint(p);
  if (triangle) *triangle = nearest.triangle;
  const double d = std::sqrt(nearest.distance_squared);
  return Inside(p, nearest) ? d : -d;
}

// The branch and bound of mesh_depth.h, best first over both directions:
// the sub-triangle with the largest upper bound is refined next, so the
// deepest place is found first (a yes/no question stops there; a
// measurement's lower bound rises early and settles the rest).
class SurfaceDepthSearch {
 public:
  SurfaceDepthSearch(const SurfaceDepthOptions& options, double floor, int max_sub_triangles = kMaxSubTriangles)
      : options_(options),
        floor_(floor),
        shift_(std::max(options.resolution / 2, 4 * floor)),
        max_sub_triangles_(max_sub_triangles) {}

  // Direction k: the triangles of `a`, moved into b's coordinates by a_to_b,
  // against `b`; b_to_world maps b's coordinates to the world (for region).
  // `skip` (or null): triangles of `a` left out; `target_mask` (or null):
  // boxes of b's coordinates where points of `a` do not count. `sweep`
  // (b's coordinates): a's points move by s * sweep, s in [0, 1]
  // (MeasureSweptSurfaceDepth); zero: they stay.
  void AddDirection(int k, const DepthSurface& a, const Eigen::Isometry3d& a_to_b, const DepthSurface& b,
                    const Eigen::Isometry3d& b_to_world, const std::vector<char>* skip = nullptr,
                    const DepthMask* target_mask = nullptr, const Eigen::Vector3d& sweep = Eigen::Vector3d::Zero()) {
    target_[k] = &b;
    mask_[k] = target_mask;
    source_outward_[k] = a.oriented_ && a.solid_ ? a.outward_ : 0.0;
    to_world_[k] = b_to_world;
    const Eigen::Isometry3d b_to_a = a_to_b.inverse();
    // b's box in a's coordinates, at both ends of the sweep.
    const Eigen::Vector3d back = b_to_a.linear() * sweep;
    Aabb query = b.box_.Transformed(b_to_a);
    query.Extend(Aabb{query.min - back, query.max - back});
    a.bvh_.ForEachTriangleNear(query.min, query.max, [&](int t) {
      if (skip && (*skip)[t]) return true;
      const auto& tri = a.triangles_[t];
      Push(Node{std::numeric_limits<double>::infinity(),
                {a_to_b * a.vertices_[tri[0]], a_to_b * a.vertices_[tri[1]], a_to_b * a.vertices_[tri[2]]},
                k,
                -1,
                sweep});
      return true;
    });
  }

  SurfaceDepth Run() {
    // Without a region to measure, once the best bound left is settled so
    // is every other: the answer's upper bound is that bound.
    const bool whole = std::isfinite(options_.region_depth);
    while (!heap_.empty()) {
      if (!whole && Settled(heap_.front().priority)) {
        result_.upper = std::max(result_.upper, heap_.front().priority);
        break;
      }
      std::pop_heap(heap_.begin(), heap_.end(), ByPriority);
      const Node node = std::move(heap_.back());
      heap_.pop_back();
      if (!Evaluate(node)) break;
    }
    result_.region_area = std::max(area_[0], area_[1]);
    result_.upper = std::max(result_.upper, result_.lower);
    return result_;
  }

 private:
  using Corners = std::array<Eigen::Vector3d, 3>;
  struct Node {
    double priority;  // the parent's upper bound
    Corners t;
    int direction;
    int hint;           // the parent's nearest triangle
    Eigen::Vector3d w;  // swept along this (the prism of t and t + w); zero: t itself
  };
  static bool ByPriority(const Node& x, const Node& y) { return x.priority < y.priority; }

  // The unit direction into the shell a sub-triangle belongs to (against
  // its outward normal); zero where that shell is not closed and oriented.
  // Where two surfaces are in contact, a piece of one moved that way leaves
  // the other, whatever the other's nearest feature to its centre (a long
  // facet of a pin through its bore: the nearest feature to its middle is
  // a rim or a face of the bore's part, whose normal does not free it).
  Eigen::Vector3d IntoOwnShell(const Node& node) const {
    const double sign = source_outward_[node.direction];
    const Eigen::Vector3d cross = (node.t[1] - node.t[0]).cross(node.t[2] - node.t[0]);
    const double norm = cross.norm();
    if (sign == 0 || !(norm > 0)) return Eigen::Vector3d::Zero();
    return (-sign / norm) * cross;
  }

  void Push(Node node) {
    heap_.push_back(std::move(node));
    std::push_heap(heap_.begin(), heap_.end(), ByPriority);
  }

  // Measuring (decide infinite): within the resolution of the best lower
  // bound, or below `settle`. Deciding: also below the threshold.
  bool Settled(double upper) const {
    return upper <= WithinResolution() || upper <= options_.settle ||
           (std::isfinite(options_.decide) && upper <= options_.decide);
  }
  // The bound that is within the resolution of the best lower bound.
  double WithinResolution() const {
    const double coarse =
        result_.lower > options_.coarse_above ? SurfaceDepthOptions::kCoarseShare * result_.lower : 0.0;
    return result_.lower + std::max(options_.resolution, coarse);
  }

  // Bounds one sub-triangle and splits it when unsettled; false when the
  // lower bound exceeded options.decide (the question is answered).
  bool Evaluate(const Node& node) {
    if (!node.w.isZero(0)) return EvaluateSwept(node);
    const Corners& t = node.t;
    const DepthSurface& b = *target_[node.direction];
    const DepthMask* mask = mask_[node.direction];
    if (mask && mask->ContainsAll(t)) return true;  // wholly in a fastener's box
    ++result_.sub_triangles;
    const Eigen::Vector3d m = (t[0] + t[1] + t[2]) / 3.0;
    double radius = 0;
    for (const auto& c : t) radius = std::max(radius, (c - m).norm());
    const TriangleBvh::Nearest nearest = b.bvh_.NearestPoint(m, node.hint);
    if (nearest.triangle < 0) return true;
    const double d = std::sqrt(nearest.distance_squared);
    const bool inside = b.Inside(m, nearest);
    if (!inside && d >= radius) return true;  // wholly outside b
    // Outside, and crossing no triangle of b: wholly outside too (a surface
    // at a small gap, or in contact, costs no refinement).
    if (!inside && !b.MayMeet(t, floor_)) return true;
    // A centre in a fastener's box attains nothing; its bound still holds.
    const bool counts = inside && !(mask && mask->Contains(m));
    const bool deep = counts && d > options_.region_depth;
    if (counts) {
      result_.lower = std::max(result_.lower, d);
      if (deep) result_.region.Extend(to_world_[node.direction] * m);
      if (result_.lower > options_.decide) return false;
    }
    const bool measuring_region = std::isfinite(options_.region_depth);
    const double upper = TriangleUpper(b, t, nearest, inside, d, radius, measuring_region, 0.0, IntoOwnShell(node));
    if (Settled(upper) || radius < floor_ || ++made_ > max_sub_triangles_) {
      result_.upper = std::max(result_.upper, upper);
      if (deep) {
        const Eigen::Vector3d cross = (t[1] - t[0]).cross(t[2] - t[0]);
        const double area = 0.5 * cross.norm();
        area_[node.direction] += area;
        if (area > 0) {
          const Eigen::Vector3d n = to_world_[node.direction].linear() * (cross / (2 * area));
          result_.region_normals += area * n * n.transpose();
        }
      }
      return true;
    }
    // Longest-edge bisection: a CAD sliver (a cylinder's facet, long and
    // narrow) is cut across its length, where midpoint subdivision would
    // quarter it into slivers again.
    int longest = 0;
    for (int k = 1; k < 3; ++k)
      if ((t[(k + 1) % 3] - t[k]).squaredNorm() > (t[(longest + 1) % 3] - t[longest]).squaredNorm()) longest = k;
    const Eigen::Vector3d& p = t[longest];
    const Eigen::Vector3d& q = t[(longest + 1) % 3];
    const Eigen::Vector3d& r = t[(longest + 2) % 3];
    const Eigen::Vector3d mid = 0.5 * (p + q);
    Push(Node{upper, {p, mid, r}, node.direction, nearest.triangle, node.w});
    Push(Node{upper, {mid, q, r}, node.direction, nearest.triangle, node.w});
    return true;
  }

  // An upper bound on the depth of every point of the convex hull of
  // `corners` from b's faces. A convex b lies behind each face plane, so a
  // point inside is at most its height below any of them from b's surface
  // (and a point outside has no depth): per plane an affine bound, largest
  // at a corner, that holds past the face's edges too (a pin along the rim
  // of a sleeve, a face resting on a box's top face); the least of them
  // (only where `planes`). Otherwise the distance to the convex patch of
  // `triangle` (convex, so largest at a corner).
  template <typename Points>
  double FaceBound(const DepthSurface& b, const Points& corners, int triangle, bool planes) const {
    double bound = 0;
    if (b.convex_ && planes && !b.planes_.empty()) {
      bound = std::numeric_limits<double>::infinity();
      for (const auto& [normal, offset] : b.planes_) {
        double plane = 0;
        for (const auto& c : corners) plane = std::max(plane, offset - c.dot(normal));
        bound = std::min(bound, plane);
      }
    } else {
      for (const auto& c : corners) bound = std::max(bound, b.PatchDistance(c, triangle));
    }
    return bound;
  }

  // The upper bound on the depth of every point of sub-triangle t (centre
  // inside b or not, at distance d from its nearest point, corners within
  // `radius` of the centre). `offset`: added before asking whether a bound
  // is settled (a swept prism's points are within it of t's). The plane
  // bounds settle sub-triangles that straddle the edge of an overlap early,
  // whole; a region's area (a fit's layer) is measured with the patch bound
  // alone, as before they were added.
  double TriangleUpper(const DepthSurface& b, const Corners& t, const TriangleBvh::Nearest& nearest, bool inside,
                       double d, double radius, bool measuring_region, double offset,
                       const Eigen::Vector3d& into_own_shell) const {
    double upper = inside ? d + radius : radius;
    upper = std::min(upper, FaceBound(b, t, nearest.triangle, !measuring_region));
    // A region's area (a fit's layer) is measured with the patch bound
    // alone, as before the bounds below were added.
    if (measuring_region) return upper;
    const auto unsettled = [&] { return !Settled(upper + offset); };
    // A sub-triangle across a face of b (mesh_depth.h, StraddleBound).
    if (unsettled()) upper = std::min(upper, b.FaceRegionBound(t, nearest.triangle, floor_, upper));
    if (unsettled()) upper = std::min(upper, b.StraddleBound(t, nearest.triangle, floor_));
    if (unsettled()) upper = std::min(upper, b.ShiftOffBound(t, nearest, shift_, floor_, into_own_shell));
    const bool deciding = std::isfinite(options_.decide);
    // A yes/no question or a slack, where depths below `settle` do not
    // matter: a move by that much settles a sub-triangle as well, and frees
    // more, also halfway between its own shell's inward normal and b's
    // normal at a corner (ShiftOffBound). Not for a measurement: its number
    // (a report's) would then read `settle` for any depth below it.
    const double settle = options_.settle - offset;
    if (unsettled() && deciding && settle > shift_ && std::isfinite(settle))
      upper = std::min(upper, b.ShiftOffBound(t, nearest, settle, floor_, into_own_shell, true));
    // A yes/no question (a validity check) settles a sub-triangle that moved
    // off b by as much as the depth allowed lies wholly outside: no point of
    // it is deeper (a fit or a tessellation overlap: each polygon's corners
    // stand into the other's faces all along them, and this settles them
    // whole, where every other bound refines along each line where the
    // faces cross: dm1's bolt in its bore, 0.2 s a check before).
    const double allowed = options_.decide - offset;
    if (unsettled() && deciding && allowed > shift_)
      upper = std::min(upper, b.ShiftOffBound(t, nearest, allowed, floor_, into_own_shell));
    // A measurement: a move by the resolution above the best lower bound
    // settles a sub-triangle too (its points are then within the resolution
    // of the answer), where a move by resolution / 2 (shift_) did not. A
    // rod in its bores, each a polygon of other corners, is 0.025 mm deep
    // along all of its length: the bounds above refine each facet along
    // every line where the polygons cross (as1's rod: 0.5 s a measure), one
    // such move settles it. Not past `coarse_above` while the lower bound
    // is below it: a pose's slack would then read too deep where it is not.
    if (unsettled() && !deciding) {
      const double within = WithinResolution();
      const double measured =
          (result_.lower > options_.coarse_above ? within : std::min(within, options_.coarse_above)) - offset;
      if (measured > shift_)
        upper = std::min(upper, b.ShiftOffBound(t, nearest, measured, floor_, into_own_shell, true));
    }
    return upper;
  }

  // Whether the prism of t and t + w may touch b's surface (PrismApartFromTriangle).
  bool PrismMayMeet(const DepthSurface& b, const Corners& t, const Eigen::Vector3d& w, double gap) const {
    Eigen::Vector3d lo = t[0], hi = t[0];
    for (const auto& c : t) {
      lo = lo.cwiseMin(c).cwiseMin(c + w);
      hi = hi.cwiseMax(c).cwiseMax(c + w);
    }
    bool meets = false;
    b.bvh_.ForEachTriangleNear(lo.array() - gap, hi.array() + gap, [&](int k) {
      const auto& f = b.triangles_[k];
      meets = !PrismApartFromTriangle(t, w, {b.vertices_[f[0]], b.vertices_[f[1]], b.vertices_[f[2]]}, gap);
      return !meets;
    });
    return meets;
  }

  // ShiftOffBound (mesh_depth.h) for the prism of t and t + w: moved by
  // `shift` along the outward normal at its centre's nearest point, it lies
  // wholly outside b, so every point of it is within `shift` of a point
  // outside. Infinite where neither normal frees it.
  double PrismShiftOffBound(const DepthSurface& b, const Corners& t, const Eigen::Vector3d& w,
                            const TriangleBvh::Nearest& nearest, double shift,
                            const Eigen::Vector3d& into_own_shell) const {
    constexpr double kNone = std::numeric_limits<double>::infinity();
    if (!b.oriented_ || !b.solid_ || nearest.triangle < 0 || !(shift > floor_)) return kNone;
    const Eigen::Vector3d centre = (t[0] + t[1] + t[2]) / 3.0 + 0.5 * w;
    const Eigen::Vector3d directions[3] = {into_own_shell, b.face_normal_[nearest.triangle],
                                           b.NormalAtNearest(centre, nearest)};
    for (int k = 0; k < 3; ++k) {
      if (k == 2 && directions[2].isApprox(directions[1])) break;
      const double length = directions[k].norm();
      if (!(length > 0)) continue;
      const Eigen::Vector3d move = (shift / length) * directions[k];
      const Corners moved = {t[0] + move, t[1] + move, t[2] + move};
      const Eigen::Vector3d moved_centre = centre + move;
      if (b.Inside(moved_centre, b.bvh_.NearestPoint(moved_centre, nearest.triangle))) continue;
      if (PrismMayMeet(b, moved, w, floor_)) continue;
      return shift;
    }
    return kNone;
  }

  // Whether convex piece `piece` may touch b's surface, leaving out
  // `triangle` and the triangles of its group (group_of: patch_of_ or
  // region_of_; null: none).
  bool PieceMayMeet(const DepthSurface& b, const ConvexPiece& piece, double gap, const std::vector<int>* group_of,
                    int triangle) const {
    const int group = group_of ? (*group_of)[triangle] : -1;
    Eigen::Vector3d lo = piece.corners.front(), hi = lo;
    for (const auto& c : piece.corners) lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
    bool meets = false;
    b.bvh_.ForEachTriangleNear(lo.array() - gap, hi.array() + gap, [&](int k) {
      if (k == triangle || (group >= 0 && (*group_of)[k] == group)) return true;
      const auto& f = b.triangles_[k];
      meets = !PieceApartFromTriangle(piece, {b.vertices_[f[0]], b.vertices_[f[1]], b.vertices_[f[2]]}, gap);
      return !meets;
    });
    return meets;
  }

  // StraddleBound (mesh_depth.h) for the prism of t and t + w across the
  // (raised) plane of a face F of b: the part in front is outside when its
  // centre is outside and it meets no triangle off F's flat region (or
  // patch); the part behind, a convex piece, is bounded at its corners by
  // the distance to F's patch, or to the patch nearest its centre, or by
  // the ball about its centre. F: the face nearest the prism's centre, the
  // centre of either end of it, or one of its six corners (where a stretch
  // of the motion carries a part out over a rim, a pin's edge out of its
  // bore's mouth, whose face then bounds the part behind it; or where a
  // piece of one surface passes under a convex edge of the other).
  // Infinite where no face gives a bound.
  double PrismStraddleBound(const DepthSurface& b, const Corners& t, const Eigen::Vector3d& w,
                            const TriangleBvh::Nearest& nearest) const {
    constexpr double kNone = std::numeric_limits<double>::infinity();
    if (!b.oriented_ || !b.solid_) return kNone;
    const Eigen::Vector3d start = (t[0] + t[1] + t[2]) / 3.0;
    int faces[9] = {nearest.triangle, b.bvh_.NearestPoint(start, nearest.triangle).triangle,
                    b.bvh_.NearestPoint(start + w, nearest.triangle).triangle};
    for (int k = 0; k < 3; ++k) {
      faces[3 + k] = b.bvh_.NearestPoint(t[k], nearest.triangle).triangle;
      faces[6 + k] = b.bvh_.NearestPoint(t[k] + w, nearest.triangle).triangle;
    }
    const double raise = 2 * b.flat_;
    double best = kNone;
    for (int k = 0; k < 9; ++k) {
      const int face = faces[k];
      if (face < 0 || std::find(faces, faces + k, face) != faces + k) continue;
      const Eigen::Vector3d& normal = b.face_normal_[face];
      if (normal.squaredNorm() == 0) continue;
      // The plane raised so that the triangles left out of the crossing
      // test below lie behind it: F's flat region (its coplanar neighbours,
      // off the plane by at most its deviation), else F's patch.
      const int region = b.region_of_.empty() ? -1 : b.region_of_[face];
      const int patch = b.patch_of_[face];
      // And by twice the gap the crossing test keeps: the faces that meet F
      // at its edges (a convex edge of b: they lie behind F's plane) are
      // then that far from the part in front along F's normal.
      const double lift = raise + (region >= 0 ? b.regions_[region].deviation : 0.0) + 2 * floor_;
      const Eigen::Vector3d origin = patch >= 0 ? b.patches_[patch].origin : b.vertices_[b.triangles_[face][0]];
      const PrismSplit split = SplitPrismAtPlane(t, w, normal, normal.dot(origin) + lift);
      if (split.cut.empty() || split.behind.corners.size() == split.cut.size()) continue;
      if (PieceMayMeet(b, split.front, floor_, region >= 0 ? &b.region_of_ : &b.patch_of_, face)) continue;
      // A point of the part in front outside (its centre): then all of it,
      // as it crosses no triangle.
      Eigen::Vector3d front_centre = Eigen::Vector3d::Zero();
      for (const auto& p : split.front.corners) front_centre += p;
      front_centre /= static_cast<double>(split.front.corners.size());
      if (b.Inside(front_centre, b.bvh_.NearestPoint(front_centre, face))) continue;
      // The part behind.
      double to_face = 0;
      Eigen::Vector3d centre = Eigen::Vector3d::Zero();
      for (const auto& p : split.behind.corners) {
        to_face = std::max(to_face, b.PatchDistance(p, face));
        centre += p;
      }
      centre /= static_cast<double>(split.behind.corners.size());
      const TriangleBvh::Nearest near = b.bvh_.NearestPoint(centre, face);
      double radius = 0, to_near = 0;
      for (const auto& p : split.behind.corners) {
        radius = std::max(radius, (p - centre).norm());
        to_near = std::max(to_near, b.PatchDistance(p, near.triangle));
      }
      const double ball = (b.Inside(centre, near) ? std::sqrt(near.distance_squared) : 0.0) + radius;
      best = std::min(best, std::min({to_face, to_near, ball}));
    }
    return best;
  }

  // Evaluate for a swept node: the prism of t and t + w (MeasureSweptSurfaceDepth).
  bool EvaluateSwept(const Node& node) {
    const Corners& t = node.t;
    const Eigen::Vector3d& w = node.w;
    const DepthSurface& b = *target_[node.direction];
    const DepthMask* mask = mask_[node.direction];
    const std::array<Eigen::Vector3d, 6> corners = {t[0], t[1], t[2], t[0] + w, t[1] + w, t[2] + w};
    if (mask) {
      // Wholly in one fastener's box (a box is convex: its six corners).
      for (const auto& box : mask->boxes)
        if (std::all_of(corners.begin(), corners.end(), [&](const Eigen::Vector3d& c) { return box.Contains(c); }))
          return true;
    }
    ++result_.sub_triangles;
    // The centre: a point of a's surface at the stretch's middle.
    const Eigen::Vector3d m = (t[0] + t[1] + t[2]) / 3.0 + 0.5 * w;
    double radius = 0;
    for (const auto& c : corners) radius = std::max(radius, (c - m).norm());
    const TriangleBvh::Nearest nearest = b.bvh_.NearestPoint(m, node.hint);
    if (nearest.triangle < 0) return true;
    const double d = std::sqrt(nearest.distance_squared);
    const bool inside = b.Inside(m, nearest);
    if (!inside && d >= radius) return true;                     // wholly outside b
    if (!inside && !PrismMayMeet(b, t, w, floor_)) return true;  // outside, crossing nothing
    const bool counts = inside && !(mask && mask->Contains(m));
    if (counts) {
      result_.lower = std::max(result_.lower, d);
      if (result_.lower > options_.decide) return false;
    }
    // Bounds of the prism itself.
    double upper = inside ? d + radius : radius;
    upper = std::min(upper, FaceBound(b, corners, nearest.triangle, true));
    if (!Settled(upper)) upper = std::min(upper, PrismShiftOffBound(b, t, w, nearest, shift_, IntoOwnShell(node)));
    // A yes/no question settles a prism that moved off b by as much as the
    // depth allowed lies wholly outside: no point of it is deeper (a part
    // drawn along a fit or a tessellation overlap: each polygon's corners
    // stand into the other's faces all the way, as deep as at the start,
    // and this settles them whole, where every other bound refines along
    // each line where the faces cross).
    if (!Settled(upper) && std::isfinite(options_.decide))
      upper = std::min(upper, PrismShiftOffBound(b, t, w, nearest, options_.decide, IntoOwnShell(node)));
    if (!Settled(upper)) upper = std::min(upper, PrismStraddleBound(b, t, w, nearest));
    // And of the triangle half way, t + w / 2, whose centre is m: every
    // point of the prism is within |w| / 2 of one of it, and the depth is
    // 1-Lipschitz (a short stretch across a face, which the face-region and
    // straddle bounds of a triangle settle).
    if (!Settled(upper)) {
      const double half = 0.5 * w.norm();
      const Corners middle = {t[0] + 0.5 * w, t[1] + 0.5 * w, t[2] + 0.5 * w};
      double middle_radius = 0;
      for (const auto& c : middle) middle_radius = std::max(middle_radius, (c - m).norm());
      const double middle_upper =
          !inside && (d >= middle_radius || !b.MayMeet(middle, floor_))
              ? 0.0
              : TriangleUpper(b, middle, nearest, inside, d, middle_radius, false, half, IntoOwnShell(node));
      upper = std::min(upper, middle_upper + half);
    }
    if (Settled(upper) || radius < floor_ || ++made_ > max_sub_triangles_) {
      result_.upper = std::max(result_.upper, upper);
      return true;
    }
    int longest = 0;
    for (int k = 1; k < 3; ++k)
      if ((t[(k + 1) % 3] - t[k]).squaredNorm() > (t[(longest + 1) % 3] - t[longest]).squaredNorm()) longest = k;
    const Eigen::Vector3d& p = t[longest];
    const Eigen::Vector3d& q = t[(longest + 1) % 3];
    const Eigen::Vector3d& r = t[(longest + 2) % 3];
    if (w.squaredNorm() >= (q - p).squaredNorm()) {
      // Across the motion: two halves of the stretch.
      const Eigen::Vector3d half = 0.5 * w;
      Push(Node{upper, t, node.direction, nearest.triangle, half});
      Push(Node{upper, {t[0] + half, t[1] + half, t[2] + half}, node.direction, nearest.triangle, half});
      return true;
    }
    const Eigen::Vector3d mid = 0.5 * (p + q);
    Push(Node{upper, {p, mid, r}, node.direction, nearest.triangle, w});
    Push(Node{upper, {mid, q, r}, node.direction, nearest.triangle, w});
    return true;
  }

  SurfaceDepthOptions options_;
  double floor_;
  // How far ShiftOffBound moves a sub-triangle: a bound within the
  // resolution (settled), and well beyond the gap MayMeet keeps.
  double shift_;
  const DepthSurface* target_[2] = {nullptr, nullptr};
  const DepthMask* mask_[2] = {nullptr, nullptr};
  // Per direction: the sign that turns a sub-triangle's corner order into
  // its own shell's outward normal (the corners keep the order of the
  // shell's triangles: bisection and the rigid move to b keep it); 0 where
  // the shell is not closed and oriented.
  double source_outward_[2] = {0, 0};
  Eigen::Isometry3d to_world_[2];
  std::vector<Node> heap_;
  SurfaceDepth result_;
  int max_sub_triangles_;
  int made_ = 0;
  double area_[2] = {0, 0};
};

SurfaceDepth MeasureSurfaceDepth(const DepthSurface& a, const Eigen::Isometry3d& pose_a, const DepthSurface& b,
                                 const SurfaceDepthOptions& options, const DepthMask* mask_a) {
  // Sub-triangles smaller than this are not made (their bound is kept).
  const double scale = std::max(a.box().Diagonal(), b.box().Diagonal());
  const double floor = std::max(options.resolution / 8, 1e-9 * scale);
  SurfaceDepthSearch search(options, floor);
  search.AddDirection(0, a, pose_a, b, Eigen::Isometry3d::Identity(), mask_a ? &mask_a->skip_triangle : nullptr);
  search.AddDirection(1, b, pose_a.inverse(), a, pose_a, nullptr, mask_a);
  return search.Run();
}

bool SweptSurfacesMayMeet(const std::vector<Eigen::Vector3d>& vertices,
                          const std::vector<std::array<int, 3>>& triangles, const Eigen::Isometry3d& pose_a,
                          const Eigen::Vector3d& move, const DepthSurface& b, double gap) {
  const Aabb& box = b.box();
  for (const auto& tri : triangles) {
    const std::array<Eigen::Vector3d, 3> t = {pose_a * vertices[tri[0]], pose_a * vertices[tri[1]],
                                              pose_a * vertices[tri[2]]};
    Eigen::Vector3d lo = t[0], hi = t[0];
    for (const auto& c : t) {
      lo = lo.cwiseMin(c).cwiseMin(c + move);
      hi = hi.cwiseMax(c).cwiseMax(c + move);
    }
    lo.array() -= gap;
    hi.array() += gap;
    if ((hi.array() < box.min.array()).any() || (lo.array() > box.max.array()).any()) continue;
    bool meets = false;
    b.bvh().ForEachTriangleNear(lo, hi, [&](int k) {
      const auto& f = b.triangles()[k];
      meets = !PrismApartFromTriangle(t, move, {b.vertices()[f[0]], b.vertices()[f[1]], b.vertices()[f[2]]}, gap);
      return !meets;
    });
    if (meets) return true;
  }
  return false;
}

SurfaceDepth MeasureSweptSurfaceDepth(const DepthSurface& a, const Eigen::Isometry3d& pose_a,
                                      const Eigen::Vector3d& move, const DepthSurface& b,
                                      const SurfaceDepthOptions& options, int max_sub_triangles,
                                      const DepthMask* mask_a) {
  SurfaceDepthOptions swept = options;
  swept.region_depth = std::numeric_limits<double>::infinity();
  const double scale = std::max(a.box().Diagonal(), b.box().Diagonal());
  const double floor = std::max(options.resolution / 8, 1e-9 * scale);
  SurfaceDepthSearch search(swept, floor, max_sub_triangles);
  // a's points move by s * move in b's coordinates; b's points, in a's
  // coordinates, by -s * (a's rotation)^T move.
  search.AddDirection(0, a, pose_a, b, Eigen::Isometry3d::Identity(), mask_a ? &mask_a->skip_triangle : nullptr,
                      nullptr, move);
  search.AddDirection(1, b, pose_a.inverse(), a, pose_a, nullptr, mask_a, -(pose_a.linear().transpose() * move));
  return search.Run();
}

}  // namespace ausbau
