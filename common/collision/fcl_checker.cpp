#include "collision/fcl_checker.h"

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>
#include <fcl/geometry/bvh/BVH_model.h>

namespace ausbau {
namespace {

using Bvh = fcl::BVHModel<fcl::OBBRSSd>;

std::shared_ptr<Bvh> BuildBvh(const TriangleMesh& mesh) {
  std::vector<fcl::Vector3d> points(mesh.vertices.begin(), mesh.vertices.end());
  std::vector<fcl::Triangle> triangles;
  triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) triangles.emplace_back(t[0], t[1], t[2]);
  auto model = std::make_shared<Bvh>();
  model->beginModel(static_cast<int>(triangles.size()), static_cast<int>(points.size()));
  model->addSubModel(points, triangles);
  model->endModel();
  model->computeLocalAABB();
  return model;
}

fcl::Transform3d ToFcl(const Pose& pose) {
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.linear() = pose.q.toRotationMatrix();
  tf.translation() = pose.t;
  return tf;
}

}  // namespace

struct FclCollisionChecker::Models {
  std::shared_ptr<Bvh> robot;
  std::shared_ptr<Bvh> environment;
};

FclCollisionChecker::FclCollisionChecker(const TriangleMesh& robot, const TriangleMesh& environment)
    : models_(std::make_unique<Models>()) {
  models_->robot = BuildBvh(robot);
  models_->environment = BuildBvh(environment);
}

FclCollisionChecker::~FclCollisionChecker() = default;

bool FclCollisionChecker::InCollision(const Pose& pose) const {
  // The geometry-level overload keeps no state in shared objects, so
  // concurrent queries are safe.
  fcl::CollisionRequestd request;  // one contact is enough: an early out
  fcl::CollisionResultd result;
  fcl::collide(models_->robot.get(), ToFcl(pose), models_->environment.get(),
               fcl::Transform3d::Identity(), request, result);
  return result.isCollision();
}

double FclCollisionChecker::Distance(const Pose& pose) const {
  fcl::DistanceRequestd request;
  fcl::DistanceResultd result;
  fcl::distance(models_->robot.get(), ToFcl(pose), models_->environment.get(),
                fcl::Transform3d::Identity(), request, result);
  return std::max(0.0, result.min_distance);
}

}  // namespace ausbau
