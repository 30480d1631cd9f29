#include "collision/fcl_checker.h"

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include "collision/fcl_model.h"

namespace ausbau {
namespace {

fcl::Transform3d ToFcl(const Pose& pose) {
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.linear() = pose.q.toRotationMatrix();
  tf.translation() = pose.t;
  return tf;
}

}  // namespace

struct FclCollisionChecker::Models {
  std::shared_ptr<FclModel> robot;
  std::shared_ptr<FclModel> environment;
};

FclCollisionChecker::FclCollisionChecker(const TriangleMesh& robot, const TriangleMesh& environment)
    : models_(std::make_unique<Models>()) {
  models_->robot = BuildFclModel(robot);
  models_->environment = BuildFclModel(environment);
}

FclCollisionChecker::~FclCollisionChecker() = default;

bool FclCollisionChecker::InCollision(const Pose& pose) const {
  // The geometry-level overload keeps no state in shared objects, so
  // concurrent queries are safe.
  fcl::CollisionRequestd request;  // one contact is enough: an early out
  fcl::CollisionResultd result;
  fcl::collide(models_->robot.get(), ToFcl(pose), models_->environment.get(), fcl::Transform3d::Identity(), request,
               result);
  return result.isCollision();
}

double FclCollisionChecker::Distance(const Pose& pose) const {
  fcl::DistanceRequestd request;
  fcl::DistanceResultd result;
  fcl::distance(models_->robot.get(), ToFcl(pose), models_->environment.get(), fcl::Transform3d::Identity(), request,
                result);
  return std::max(0.0, result.min_distance);
}

}  // namespace ausbau
