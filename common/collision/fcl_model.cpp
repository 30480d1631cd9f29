#include "collision/fcl_model.h"

namespace ausbau {

std::shared_ptr<FclModel> BuildFclModel(const std::vector<Eigen::Vector3d>& vertices,
                                        const std::vector<std::array<int, 3>>& triangles) {
  std::vector<fcl::Vector3d> points(vertices.begin(), vertices.end());
  std::vector<fcl::Triangle> fcl_triangles;
  fcl_triangles.reserve(triangles.size());
  for (const auto& t : triangles) fcl_triangles.emplace_back(t[0], t[1], t[2]);
  auto model = std::make_shared<FclModel>();
  model->beginModel(static_cast<int>(fcl_triangles.size()), static_cast<int>(points.size()));
  model->addSubModel(points, fcl_triangles);
  model->endModel();
  model->computeLocalAABB();
  return model;
}

}  // namespace ausbau
