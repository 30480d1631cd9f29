// A small non-convex solid for tests: a lug on the plane z = 0 reaching to
// z = -4 below the origin, its face towards (1, 1, 1) dented in to
// (0.5, 0.5, -0.5). Six triangles, closed.
#pragma once

#include <array>
#include <vector>

#include "geometry/mesh.h"

namespace ausbau::testing {

inline void AppendDentedLug(TriangleMesh* mesh) {
  const int base = static_cast<int>(mesh->vertices.size());
  for (const Eigen::Vector3d& v :
       std::vector<Eigen::Vector3d>{{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, -4}, {0.5, 0.5, -0.5}})
    mesh->vertices.push_back(v);
  for (auto tri : std::vector<std::array<int, 3>>{{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 4, 2}, {2, 4, 3}, {3, 4, 1}}) {
    for (int& i : tri) i += base;
    mesh->triangles.push_back(tri);
  }
}

}  // namespace ausbau::testing
