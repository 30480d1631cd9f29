#include "geometry/shells.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <unordered_map>

#include "geometry/weld.h"

namespace ausbau {
namespace {

// Directions closer than this angle (radians) are one direction. Meshes
// stored in single precision metres from the origin (STL) carry coordinate
// noise of ~1e-4 mm, which tilts a 1 mm face by a few 1e-4 rad; a merged
// direction only makes the separating-axis depth larger (conservative), never
// smaller.
constexpr double kSameDirection = 1e-3;

int Find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Unit directions in cells of side kSameDirection (a chord is no longer
// than its angle): those within kSameDirection of a direction lie in the 27
// cells about its own. A curved shell's triangles nearly all point their
// own way, and a search through every direction so far made Analyse
// quadratic (CAx-IF s1's body, 99,000 triangles: 30 s a shell).
class DirectionIndex {
 public:
  void Insert(const Eigen::Vector3d& unit, int index) { cells_[Key(Cell(unit))].push_back(index); }
  // The smallest inserted index whose direction `accept`s (called only for
  // directions within kSameDirection of `unit`, and perhaps a few more);
  // -1 if none.
  template <typename Accept>
  int First(const Eigen::Vector3d& unit, const Accept& accept) const {
    const Eigen::Vector3i cell = Cell(unit);
    int first = -1;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find(Key(cell + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells_.end()) continue;
          for (const int index : it->second)
            if ((first < 0 || index < first) && accept(index)) first = index;
        }
    return first;
  }

 private:
  static Eigen::Vector3i Cell(const Eigen::Vector3d& unit) {
    return (unit / kSameDirection).array().floor().cast<int>();
  }
  static std::uint64_t Key(const Eigen::Vector3i& cell) {
    const auto part = [](int c) { return static_cast<std::uint64_t>(c + (1 << 20)) & ((1u << 21) - 1); };
    return part(cell.x()) << 42 | part(cell.y()) << 21 | part(cell.z());
  }
  std::unordered_map<std::uint64_t, std::vector<int>> cells_;
};

// Groups unit directions up to sign; each group's representative is the
// normalized weighted sum of its members (sign-aligned to the first).
class DirectionSet {
 public:
  int Add(const Eigen::Vector3d& unit, double weight) {
    // The first group whose first direction is within kSameDirection of
    // either sign of `unit`.
    const double same = std::cos(kSameDirection);
    const auto along = [&](int i) { return first_[i].dot(unit) >= same; };
    const auto against = [&](int i) { return first_[i].dot(unit) <= -same; };
    const int a = index_.First(unit, along), b = index_.First(-unit, against);
    const int i = a < 0 ? b : b < 0 ? a : std::min(a, b);
    if (i >= 0) {
      const double dot = first_[i].dot(unit);
      sum_[i] += (dot >= 0 ? weight : -weight) * unit;
      return i;
    }
    index_.Insert(unit, static_cast<int>(first_.size()));
    first_.push_back(unit);
    sum_.push_back(weight * unit);
    return static_cast<int>(first_.size()) - 1;
  }
  std::vector<Eigen::Vector3d> Directions() const {
    std::vector<Eigen::Vector3d> out;
    for (std::size_t i = 0; i < sum_.size(); ++i) {
      const double n = sum_[i].norm();
      out.push_back(n > 0 ? Eigen::Vector3d(sum_[i] / n) : first_[i]);
    }
    return out;
  }

 private:
  std::vector<Eigen::Vector3d> first_, sum_;
  DirectionIndex index_;  // of first_
};

void Analyse(Shell& shell, double stored_magnitude) {
  for (const auto& v : shell.vertices) shell.box.Extend(v);
  shell.center = shell.box.Center();
  for (const auto& v : shell.vertices) shell.radius = std::max(shell.radius, (v - shell.center).norm());

  // Closed: every undirected edge used exactly twice.
  std::map<std::pair<int, int>, std::vector<int>> edge_triangles;
  for (int t = 0; t < static_cast<int>(shell.triangles.size()); ++t) {
    const auto& tri = shell.triangles[t];
    for (int e = 0; e < 3; ++e) {
      const int a = tri[e], b = tri[(e + 1) % 3];
      edge_triangles[{std::min(a, b), std::max(a, b)}].push_back(t);
    }
  }
  shell.closed = !edge_triangles.empty();
  for (const auto& [edge, tris] : edge_triangles) shell.closed = shell.closed && tris.size() == 2;

  double signed_volume = 0;
  for (const auto& tri : shell.triangles) {
    const Eigen::Vector3d a = shell.vertices[tri[0]] - shell.center, b = shell.vertices[tri[1]] - shell.center,
                          c = shell.vertices[tri[2]] - shell.center;
    signed_volume += a.dot(b.cross(c)) / 6.0;
  }
  shell.volume = shell.closed ? std::abs(signed_volume) : 0.0;
  if (!shell.closed) return;

  // Convex: every vertex on one side of every face plane, within a
  // tolerance for coordinate noise (relative to the shell's size and to its
  // distance from the origin, as single-precision files lose digits there).
  // Coplanar triangles are tested as one face (their area-weighted normal,
  // through their mean vertex): a finely tessellated face's small triangles
  // each tilt by the rounding of their corners, and the far side of a large
  // shell would then seem to lie on both sides of their planes.
  const double tolerance = 1e-4 * shell.radius + 1e-6 * std::max(shell.center.norm(), stored_magnitude);
  struct Face {
    Eigen::Vector3d first, sum = Eigen::Vector3d::Zero(), point_sum = Eigen::Vector3d::Zero();
    int points = 0;
  };
  std::vector<Face> faces;    // by signed direction: a box's opposite faces stay apart
  DirectionIndex face_index;  // of the faces' first normals
  // Per triangle with an area: its unit normal and twice its area, grouped
  // into face normals only once the shell is convex (a large curved shell,
  // nearly always not convex, spent a tenth of a plan's time on it).
  std::vector<std::pair<Eigen::Vector3d, double>> triangle_normal(shell.triangles.size(),
                                                                  {Eigen::Vector3d::Zero(), 0.0});
  for (std::size_t t = 0; t < shell.triangles.size(); ++t) {
    const auto& tri = shell.triangles[t];
    const Eigen::Vector3d cross =
        (shell.vertices[tri[1]] - shell.vertices[tri[0]]).cross(shell.vertices[tri[2]] - shell.vertices[tri[0]]);
    const double area2 = cross.norm();
    if (!(area2 > 1e-12 * shell.radius * shell.radius)) continue;
    const Eigen::Vector3d n = cross / area2;
    int index = face_index.First(n, [&](int f) { return faces[f].first.dot(n) >= std::cos(kSameDirection); });
    if (index < 0) {
      index = static_cast<int>(faces.size());
      face_index.Insert(n, index);
      faces.push_back(Face{n});
    }
    Face* face = &faces[index];
    face->sum += area2 * n;
    for (int k = 0; k < 3; ++k) face->point_sum += shell.vertices[tri[k]];
    face->points += 3;
    triangle_normal[t] = {n, area2};
  }
  for (const Face& face : faces) {
    const Eigen::Vector3d n = face.sum.normalized();
    const double offset = n.dot(face.point_sum / face.points);
    double lo = 0, hi = 0;
    for (const auto& v : shell.vertices) {
      const double d = n.dot(v) - offset;
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    if (lo < -tolerance && hi > tolerance) return;  // vertices on both sides: not convex
  }
  DirectionSet normals;
  std::vector<int> triangle_group(shell.triangles.size(), -1);
  for (std::size_t t = 0; t < shell.triangles.size(); ++t) {
    if (triangle_normal[t].second > 0)
      triangle_group[t] = normals.Add(triangle_normal[t].first, triangle_normal[t].second);
  }
  shell.face_normals = normals.Directions();
  if (shell.face_normals.empty()) return;

  DirectionSet edges;
  std::vector<std::vector<int>> vertex_groups(shell.vertices.size());
  for (const auto& [edge, tris] : edge_triangles) {
    const int g0 = triangle_group[tris[0]], g1 = triangle_group[tris[1]];
    for (int g : {g0, g1}) {
      if (g < 0) continue;
      for (int v : {edge.first, edge.second}) {
        auto& groups = vertex_groups[v];
        if (std::find(groups.begin(), groups.end(), g) == groups.end()) groups.push_back(g);
      }
    }
    if (g0 < 0 || g1 < 0 || g0 == g1) continue;  // inside one flat face: not a feature edge
    const Eigen::Vector3d d = shell.vertices[edge.second] - shell.vertices[edge.first];
    const double length = d.norm();
    if (length > 0) edges.Add(d / length, length);
  }
  shell.edge_directions = edges.Directions();
  for (std::size_t v = 0; v < shell.vertices.size(); ++v)
    if (vertex_groups[v].size() >= 3) shell.corners.push_back(shell.vertices[v]);
  if (shell.corners.size() < 4) shell.corners = shell.vertices;
  for (const auto& normal : shell.face_normals) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& c : shell.corners) {
      lo = std::min(lo, normal.dot(c));
      hi = std::max(hi, normal.dot(c));
    }
    shell.face_low.push_back(lo);
    shell.face_high.push_back(hi);
  }
  shell.convex = true;
}

}  // namespace

std::vector<Shell> SplitIntoShells(const TriangleMesh& mesh, double stored_magnitude) {
  // Weld positions closer than a few single-precision steps at the mesh's
  // magnitude: an STL export repeats every corner per triangle, and rounds
  // each copy on its own (1e-4 mm apart, metres from the origin).
  double magnitude = stored_magnitude;
  for (const auto& v : mesh.vertices) magnitude = std::max(magnitude, v.cwiseAbs().maxCoeff());
  const double weld = std::max(1e-6 * magnitude, 1e-12);
  std::vector<Eigen::Vector3d> positions;
  const std::vector<int> welded = WeldWithinTolerance(mesh.vertices, weld, WeldDistance::kLargestCoordinate,
                                                      Eigen::Vector3d::Zero(), weld, &positions);
  // Triangles are joined across their edges. Where several solids of a soup
  // share an edge (a plate tiled by boxes shares faces and edges), an edge
  // has more than two triangles: each triangle is joined to the one met
  // first when turning about the edge from it into its own solid (the
  // radial-edge rule: the solid's inside lies on the side opposite to the
  // triangle's normal, by its orientation), so that each box stays a shell.
  const int triangle_count = static_cast<int>(mesh.triangles.size());
  auto corner = [&](int t, int k) { return welded[mesh.triangles[t][k]]; };
  auto key_of = [](std::uint64_t a, std::uint64_t b) { return a << 32 | b; };
  // A triangle two of whose corners weld into one (a sliver thinner than the
  // weld, where a CAD export's float32 rounding or a boolean's rounding left
  // two corners micrometres apart) has no area and no edges left: it belongs
  // to no shell. Kept, it would pair with itself across its two remaining
  // edges and stand alone as an open one-triangle "shell".
  std::vector<bool> collapsed(triangle_count);
  for (int t = 0; t < triangle_count; ++t)
    collapsed[t] = corner(t, 0) == corner(t, 1) || corner(t, 1) == corner(t, 2) || corner(t, 2) == corner(t, 0);
  // (a -> b, triangle) for every directed edge, sorted: the triangles of an
  // edge lie together, in the order of their index. (A hash map of vectors
  // was a fifth of a classification of a 300,000-triangle S.)
  using EdgeOfTriangle = std::pair<std::uint64_t, int>;
  std::vector<EdgeOfTriangle> directed;
  directed.reserve(3 * static_cast<std::size_t>(triangle_count));
  for (int t = 0; t < triangle_count; ++t) {
    if (collapsed[t]) continue;
    for (int e = 0; e < 3; ++e) directed.emplace_back(key_of(corner(t, e), corner(t, (e + 1) % 3)), t);
  }
  std::sort(directed.begin(), directed.end());
  // The triangles with directed edge `key`, as a range of `directed`.
  struct EdgeTriangles {
    std::vector<EdgeOfTriangle>::const_iterator first, last;
    std::size_t size() const { return static_cast<std::size_t>(last - first); }
    int operator[](std::size_t i) const { return (first + static_cast<std::ptrdiff_t>(i))->second; }
  };
  const auto triangles_of = [&directed](std::uint64_t key) {
    const auto range =
        std::equal_range(directed.cbegin(), directed.cend(), EdgeOfTriangle{key, 0},
                         [](const EdgeOfTriangle& x, const EdgeOfTriangle& y) { return x.first < y.first; });
    return EdgeTriangles{range.first, range.second};
  };
  std::vector<int> parent(triangle_count);
  std::iota(parent.begin(), parent.end(), 0);
  auto join = [&](int x, int y) {
    const int r0 = Find(parent, x), r1 = Find(parent, y);
    if (r0 != r1) parent[std::max(r0, r1)] = std::min(r0, r1);
  };
  auto third = [&](int t, int a, int b) {
    for (int k = 0; k < 3; ++k)
      if (corner(t, k) != a && corner(t, k) != b) return corner(t, k);
    return corner(t, 0);
  };
  // Two passes: first the unambiguous edges (a finely tessellated face, a
  // box's own edges where no other solid touches), then the shared ones,
  // where a candidate already joined to the triangle settles it.
  for (int pass = 0; pass < 2; ++pass) {
    for (int t = 0; t < triangle_count; ++t) {
      if (collapsed[t]) continue;
      const Eigen::Vector3d normal =
          (positions[corner(t, 1)] - positions[corner(t, 0)]).cross(positions[corner(t, 2)] - positions[corner(t, 0)]);
      for (int e = 0; e < 3; ++e) {
        const int a = corner(t, e), b = corner(t, (e + 1) % 3);
        const EdgeTriangles candidates = triangles_of(key_of(b, a));
        if (candidates.size() == 0) {
          // Inconsistently oriented: join where the edge has one other triangle.
          const EdgeTriangles same = triangles_of(key_of(a, b));
          if (pass == 0 && same.size() == 2) join(same[0], same[1]);
          continue;
        }
        if (candidates.size() == 1) {
          if (pass == 0) join(t, candidates[0]);
          continue;
        }
        if (pass == 0) continue;
        bool settled = false;
        for (std::size_t i = 0; i < candidates.size() && !settled; ++i)
          settled = Find(parent, candidates[i]) == Find(parent, t);
        if (settled) continue;
        const Eigen::Vector3d axis = (positions[b] - positions[a]).normalized();
        auto inward = [&](int tri) {  // in the triangle's plane, from the edge to its third corner
          const Eigen::Vector3d d = positions[third(tri, a, b)] - positions[a];
          return Eigen::Vector3d(d - d.dot(axis) * axis).normalized();
        };
        const Eigen::Vector3d u = inward(t);
        const Eigen::Vector3d w = -(normal - normal.dot(axis) * axis).normalized();  // into the solid
        int best = -1;
        double best_angle = 0;
        for (std::size_t i = 0; i < candidates.size(); ++i) {
          const int c = candidates[i];
          const Eigen::Vector3d d = inward(c);
          double angle = std::atan2(d.dot(w), d.dot(u));
          if (angle <= kSameDirection) angle += 2 * M_PI;  // coincident (or behind): last
          // Overlapping solids of a soup may share an edge with a face of one
          // inside the other's wedge, or flush with it (a rail's leg and foot),
          // so the angle alone can mislead: among the locally convex
          // candidates (within half a turn) the triangle written nearest to
          // this one wins, as exports write a solid's triangles together
          // (STL: every triangle has its own vertices).
          const bool convex = angle <= M_PI + kSameDirection;
          const bool best_convex = best >= 0 && best_angle <= M_PI + kSameDirection;
          bool better;
          if (best < 0)
            better = true;
          else if (convex != best_convex)
            better = convex;
          else if (convex)
            better = std::abs(c - t) < std::abs(best - t);
          else
            better = angle < best_angle;
          if (better) best = c, best_angle = angle;
        }
        join(t, best);
      }
    }
  }
  std::vector<Shell> shells;
  std::unordered_map<int, int> shell_of_root;
  std::vector<std::unordered_map<int, int>> local_index;
  for (int t = 0; t < static_cast<int>(mesh.triangles.size()); ++t) {
    if (collapsed[t]) continue;
    const auto& tri = mesh.triangles[t];
    const int root = Find(parent, t);
    const auto [it, inserted] = shell_of_root.emplace(root, static_cast<int>(shells.size()));
    if (inserted) {
      shells.emplace_back();
      local_index.emplace_back();
    }
    Shell& shell = shells[it->second];
    auto& local = local_index[it->second];
    std::array<int, 3> out;
    for (int k = 0; k < 3; ++k) {
      const int w = welded[tri[k]];
      const auto [li, fresh] = local.emplace(w, static_cast<int>(shell.vertices.size()));
      if (fresh) shell.vertices.push_back(positions[w]);
      out[k] = li->second;
    }
    shell.triangles.push_back(out);
    shell.source_triangles.push_back(t);
  }
  for (auto& shell : shells) {
    Analyse(shell, stored_magnitude);
    shell.complete_within = mesh.cropped_to;
  }
  return shells;
}

namespace {

// The projections on a unit axis of A's corners (moved into B's frame) and
// of B's.
struct Projections {
  double a_lo, a_hi, b_lo, b_hi;
};
Projections Project(const std::vector<Eigen::Vector3d>& corners_a, const Shell& b, const Eigen::Vector3d& axis) {
  Projections x;
  x.a_lo = x.b_lo = std::numeric_limits<double>::infinity();
  x.a_hi = x.b_hi = -x.a_lo;
  for (const auto& p : corners_a) {
    const double d = axis.dot(p);
    x.a_lo = std::min(x.a_lo, d);
    x.a_hi = std::max(x.a_hi, d);
  }
  for (const auto& p : b.corners) {
    const double d = axis.dot(p);
    x.b_lo = std::min(x.b_lo, d);
    x.b_hi = std::max(x.b_hi, d);
  }
  return x;
}

// The separating axes of two convex shells, A turned by `rotation` (unit):
// both shells' face normals, then the cross products of their edge
// directions (parallel edges left out: covered by the face normals).
// `visit(axis)` returns true to stop.
template <typename Visit>
void ForEachSeparatingAxis(const Shell& a, const Eigen::Matrix3d& rotation, const Shell& b, Visit&& visit) {
  for (const auto& n : a.face_normals)
    if (visit(Eigen::Vector3d(rotation * n))) return;
  for (const auto& n : b.face_normals)
    if (visit(n)) return;
  for (const auto& ea : a.edge_directions) {
    const Eigen::Vector3d ra = rotation * ea;
    for (const auto& eb : b.edge_directions) {
      const Eigen::Vector3d c = ra.cross(eb);
      const double length = c.norm();
      if (length < 1e-9) continue;
      if (visit(Eigen::Vector3d(c / length))) return;
    }
  }
}

// A's corners in B's frame (a buffer per thread).
const std::vector<Eigen::Vector3d>& CornersIn(const Shell& a, const Eigen::Isometry3d& pose_a) {
  thread_local std::vector<Eigen::Vector3d> corners_a;
  corners_a.resize(a.corners.size());
  for (std::size_t i = 0; i < a.corners.size(); ++i) corners_a[i] = pose_a * a.corners[i];
  return corners_a;
}

}  // namespace

double ConvexSignedDepth(const Shell& a, const Eigen::Isometry3d& pose_a, const Shell& b, double stop_gap) {
  const std::vector<Eigen::Vector3d>& corners_a = CornersIn(a, pose_a);
  // The least overlap of the two projections (negative: a gap).
  double depth = std::numeric_limits<double>::infinity();
  ForEachSeparatingAxis(a, pose_a.linear(), b, [&](const Eigen::Vector3d& axis) {
    const Projections x = Project(corners_a, b, axis);
    depth = std::min(depth, std::min(x.a_hi - x.b_lo, x.b_hi - x.a_lo));
    return stop_gap > 0 && depth < -stop_gap;
  });
  return depth;
}

double ConvexSweptDepthBound(const Shell& a, const Eigen::Isometry3d& pose_a, const Eigen::Vector3d& move,
                             const Shell& b) {
  const std::vector<Eigen::Vector3d>& corners_a = CornersIn(a, pose_a);
  double bound = std::numeric_limits<double>::infinity();
  ForEachSeparatingAxis(a, pose_a.linear(), b, [&](const Eigen::Vector3d& axis) {
    const Projections x = Project(corners_a, b, axis);
    // rising = a_hi - b_lo + k s, falling = b_hi - a_lo - k s.
    const double k = axis.dot(move);
    const double rising = x.a_hi - x.b_lo, falling = x.b_hi - x.a_lo;
    const double crossing = k != 0 ? std::clamp((falling - rising) / (2 * k), 0.0, 1.0) : 0.0;
    bound = std::min(bound, std::min(rising + k * crossing, falling - k * crossing));
    return false;
  });
  return bound;
}

}  // namespace ausbau
