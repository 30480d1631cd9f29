// FCL's bounding-volume hierarchy (OBBRSS) of a triangle soup: the one place
// that turns our meshes into FCL models (the FCL checker, the strict checks
// of non-convex shells, the dense re-check).
#pragma once

#include <fcl/geometry/bvh/BVH_model.h>

#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

#include "geometry/mesh.h"

namespace ausbau {

using FclModel = fcl::BVHModel<fcl::OBBRSSd>;

std::shared_ptr<FclModel> BuildFclModel(const std::vector<Eigen::Vector3d>& vertices,
                                        const std::vector<std::array<int, 3>>& triangles);
inline std::shared_ptr<FclModel> BuildFclModel(const TriangleMesh& mesh) {
  return BuildFclModel(mesh.vertices, mesh.triangles);
}

}  // namespace ausbau
