// Triangle meshes as loaded from CAD exports: an indexed triangle soup,
// not necessarily watertight or manifold.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <limits>
#include <optional>
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
  // The box about this box's eight corners moved by `pose`: it holds every
  // point of this box, moved.
  Aabb Transformed(const Eigen::Isometry3d& pose) const {
    Aabb out;
    for (int corner = 0; corner < 8; ++corner) {
      out.Extend(pose * Eigen::Vector3d((corner & 1) ? max.x() : min.x(), (corner & 2) ? max.y() : min.y(),
                                        (corner & 4) ? max.z() : min.z()));
    }
    return out;
  }
};

struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
  // Set by CropMesh: this mesh is the part of a larger one whose triangles
  // reach into this box; every triangle of the larger mesh that does is
  // here. (What lets a shell the crop cut open answer inside-or-outside
  // near its surface as a closed one does: collision/mesh_depth.h.) A copy
  // keeps it; Append and KeepTriangles, which change the set of
  // triangles, do not; whoever moves the vertices must reset it.
  std::optional<Aabb> cropped_to;

  Aabb Bounds() const {
    Aabb box;
    for (const auto& v : vertices) box.Extend(v);
    return box;
  }
  // Appends another mesh, keeping indices valid.
  void Append(const TriangleMesh& other) {
    cropped_to.reset();  // the other mesh's triangles are no crop of the same one
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
  TriangleMesh cropped = mesh.KeepTriangles([&](std::size_t t) {
    Aabb triangle;
    for (int i : mesh.triangles[t]) triangle.Extend(mesh.vertices[i]);
    if (triangle.SeparatedFrom(box)) return false;
    if (triangle_boxes) triangle_boxes->push_back(triangle);
    return true;
  });
  // A crop of a crop is complete within both boxes.
  Aabb within = box;
  if (mesh.cropped_to) {
    within.min = within.min.cwiseMax(mesh.cropped_to->min);
    within.max = within.max.cwiseMin(mesh.cropped_to->max);
  }
  if (!within.Empty()) cropped.cropped_to = within;
  return cropped;
}

}  // namespace ausbau
