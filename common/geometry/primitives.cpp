#include "geometry/primitives.h"

#include <cmath>
#include <stdexcept>

namespace ausbau {
namespace {

double SignedArea(const std::vector<Eigen::Vector2d>& polygon) {
  double area = 0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
    area += a.x() * b.y() - b.x() * a.y();
  }
  return 0.5 * area;
}

double Cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
}

// Ear clipping of a simple polygon given counter-clockwise: triangles of
// indices into it, counter-clockwise.
std::vector<std::array<int, 3>> EarClip(const std::vector<Eigen::Vector2d>& polygon) {
  std::vector<int> left(polygon.size());
  for (std::size_t i = 0; i < left.size(); ++i) left[i] = static_cast<int>(i);
  std::vector<std::array<int, 3>> triangles;
  while (left.size() > 3) {
    bool clipped = false;
    const int n = static_cast<int>(left.size());
    for (int i = 0; i < n && !clipped; ++i) {
      const int p = left[(i + n - 1) % n], c = left[i], q = left[(i + 1) % n];
      if (Cross(polygon[p], polygon[c], polygon[q]) <= 0) continue;  // reflex
      bool empty = true;
      for (int k : left) {
        if (k == p || k == c || k == q) continue;
        if (Cross(polygon[p], polygon[c], polygon[k]) >= 0 && Cross(polygon[c], polygon[q], polygon[k]) >= 0 &&
            Cross(polygon[q], polygon[p], polygon[k]) >= 0) {
          empty = false;
          break;
        }
      }
      if (!empty) continue;
      triangles.push_back({p, c, q});
      left.erase(left.begin() + i);
      clipped = true;
    }
    if (!clipped) throw std::invalid_argument("MakePrism: the outline is not a simple polygon");
  }
  triangles.push_back({left[0], left[1], left[2]});
  return triangles;
}

}  // namespace

TriangleMesh MakeSolidOfRevolution(const std::vector<Eigen::Vector2d>& profile_in, int segments) {
  // Counter-clockwise in (r, z): then the quads below face outward.
  std::vector<Eigen::Vector2d> profile = profile_in;
  if (SignedArea(profile) < 0) profile.assign(profile_in.rbegin(), profile_in.rend());
  TriangleMesh mesh;
  const int n = static_cast<int>(profile.size());
  std::vector<std::vector<int>> index(n, std::vector<int>(segments));
  for (int i = 0; i < n; ++i) {
    const double r = profile[i].x(), z = profile[i].y();
    for (int j = 0; j < segments; ++j) {
      if (r == 0 && j > 0) {
        index[i][j] = index[i][0];
        continue;
      }
      const double angle = 2 * M_PI * j / segments;
      index[i][j] = static_cast<int>(mesh.vertices.size());
      mesh.vertices.emplace_back(r * std::cos(angle), r * std::sin(angle), z);
    }
  }
  for (int i = 0; i < n; ++i) {
    const int k = (i + 1) % n;
    for (int j = 0; j < segments; ++j) {
      const int jn = (j + 1) % segments;
      // Profile edge i -> k (counter-clockwise in (r, z)) swept from angle
      // j to jn: outward is to the right of the edge in (r, z).
      const int a = index[i][j], b = index[k][j], c = index[k][jn], d = index[i][jn];
      if (a != b && b != c && a != c) mesh.triangles.push_back({a, c, b});
      if (a != c && c != d && a != d) mesh.triangles.push_back({a, d, c});
    }
  }
  return mesh;
}

TriangleMesh MakePrism(const std::vector<Eigen::Vector2d>& outline_in, double z0, double z1) {
  std::vector<Eigen::Vector2d> outline = outline_in;
  if (SignedArea(outline) < 0) outline.assign(outline_in.rbegin(), outline_in.rend());
  const int n = static_cast<int>(outline.size());
  TriangleMesh mesh;
  for (double z : {z0, z1})
    for (const auto& p : outline) mesh.vertices.emplace_back(p.x(), p.y(), z);
  for (const auto& t : EarClip(outline)) {
    mesh.triangles.push_back({t[0], t[2], t[1]});              // bottom, facing -z
    mesh.triangles.push_back({n + t[0], n + t[1], n + t[2]});  // top, facing +z
  }
  for (int i = 0; i < n; ++i) {
    const int k = (i + 1) % n;
    mesh.triangles.push_back({i, k, n + k});
    mesh.triangles.push_back({i, n + k, n + i});
  }
  return mesh;
}

}  // namespace ausbau
