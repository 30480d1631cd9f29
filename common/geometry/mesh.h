// Triangle meshes as loaded from CAD exports: an indexed triangle soup,
// not necessarily watertight or manifold.
#pragma once

#include <Eigen/Core>
#include <array>
#include <limits>
#include <string>
#include <vector>

namespace ausbau {

struct Aabb {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d max = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());

  bool Empty() const { return (min.array() > max.array()).any(); }
  void Extend(const Eigen::Vector3d& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  void Extend(const Aabb& other) {
    min = min.cwiseMin(other.min);
    max = max.cwiseMax(other.max);
  }
  Eigen::Vector3d Center() const { return 0.5 * (min + max); }
  Eigen::Vector3d Size() const { return max - min; }
  double Diagonal() const { return Empty() ? 0.0 : (max - min).norm(); }
  bool Contains(const Eigen::Vector3d& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
  // Strictly separated along some axis (touching counts as overlap).
  bool SeparatedFrom(const Aabb& other) const {
    return (max.array() < other.min.array()).any() || (other.max.array() < min.array()).any();
  }
};

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;

  Aabb Bounds() const {
    Aabb box;
    for (const auto& v : vertices) box.Extend(v);
    return box;
  }
  // Appends another mesh, keeping indices valid.
  void Append(const TriangleMesh& other) {
    const int offset = static_cast<int>(vertices.size());
    vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
    for (auto tri : other.triangles) {
      for (int& i : tri) i += offset;
      triangles.push_back(tri);
    }
  }
  // The triangles whose index `keep(t)` accepts, in their order, with only
  // the vertices they use (in the order of first use).
  template <typename Keep>
  TriangleMesh KeepTriangles(Keep keep) const {
    TriangleMesh out;
    std::vector<int> remap(vertices.size(), -1);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
      if (!keep(t)) continue;
      std::array<int, 3> kept{};
      for (int k = 0; k < 3; ++k) {
        int& r = remap[triangles[t][k]];
        if (r < 0) {
          r = static_cast<int>(out.vertices.size());
          out.vertices.push_back(vertices[triangles[t][k]]);
        }
        kept[k] = r;
      }
      out.triangles.push_back(kept);
    }
    return out;
  }
};

// The triangles of `mesh` whose AABB overlaps `box` (touching counts), in
// their order, vertices re-indexed to those used; with `triangle_boxes`,
// each kept triangle's AABB appended to it. What S is cropped to around D
// (planning/reach_crop.h) and what the contacts are measured on
// (collision/part_contacts.h).
inline TriangleMesh CropMesh(const TriangleMesh& mesh, const Aabb& box, std::vector<Aabb>* triangle_boxes = nullptr) {
  return mesh.KeepTriangles([&](std::size_t t) {
    Aabb triangle;
    for (int i : mesh.triangles[t]) triangle.Extend(mesh.vertices[i]);
    if (triangle.SeparatedFrom(box)) return false;
    if (triangle_boxes) triangle_boxes->push_back(triangle);
    return true;
  });
}

}  // namespace ausbau
