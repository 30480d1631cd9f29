#include "collision/fcl_checker.h"

#include <mutex>

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>

#include "collision/fcl_model.h"
#include "collision/fcl_tree_walk.h"
#include "collision/swept_sphere.h"

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
  std::unique_ptr<FclTreeWalk> walk;
  double robot_radius = 0;  // D's farthest vertex from its reference point
  // SweepClear's, built on its first call (from the FCL models' own
  // copies of the meshes): most checkers never sweep.
  std::once_flag sweep_once;
  BoundingSphere robot_sphere;
  std::unique_ptr<TriangleBvh> environment_tree;
  double sweep_margin = 0;
};

FclCollisionChecker::FclCollisionChecker(const TriangleMesh& robot, const TriangleMesh& environment)
    : models_(std::make_unique<Models>()) {
  models_->robot = BuildFclModel(robot);
  models_->environment = BuildFclModel(environment);
  models_->walk = std::make_unique<FclTreeWalk>(models_->robot, models_->environment);
  for (const Eigen::Vector3d& v : robot.vertices) models_->robot_radius = std::max(models_->robot_radius, v.norm());
}

FclCollisionChecker::~FclCollisionChecker() = default;

bool FclCollisionChecker::InCollision(const Pose& pose) const {
  // FCL's trees and tests, FCL's answer, without fcl::collide's overhead
  // (collision/fcl_tree_walk.h).
  return models_->walk->Collide(pose);
}

bool FclCollisionChecker::InCollisionByFclCollide(const Pose& pose) const {
  // The geometry-level overload keeps no state in shared objects, so
  // concurrent queries are safe.
  fcl::CollisionRequestd request;  // one contact is enough: an early out
  fcl::CollisionResultd result;
  fcl::collide(models_->robot.get(), ToFcl(pose), models_->environment.get(), fcl::Transform3d::Identity(), request,
               result);
  return result.isCollision();
}

bool FclCollisionChecker::SweepClear(const Pose& a, const Pose& b) const {
  std::call_once(models_->sweep_once, [this] {
    const FclModel& robot = *models_->robot;
    const FclModel& environment = *models_->environment;
    models_->robot_sphere =
        BoundingSphere::Of(std::vector<Eigen::Vector3d>(robot.vertices, robot.vertices + robot.num_vertices));
    std::vector<std::array<int, 3>> triangles(static_cast<std::size_t>(environment.num_tris));
    for (std::size_t i = 0; i < triangles.size(); ++i) {
      const fcl::Triangle& t = environment.tri_indices[i];
      triangles[i] = {static_cast<int>(t[0]), static_cast<int>(t[1]), static_cast<int>(t[2])};
    }
    models_->environment_tree = std::make_unique<TriangleBvh>(
        std::vector<Eigen::Vector3d>(environment.vertices, environment.vertices + environment.num_vertices), triangles);
    // Far above FCL's tolerances, so that no pose FCL could call touching
    // is proved free.
    models_->sweep_margin = 1e-3 * (models_->robot_sphere.centre.norm() + models_->robot_sphere.radius);
  });
  return SweptSphereClear(models_->robot_sphere, *models_->environment_tree, a, b, models_->sweep_margin);
}

bool FclCollisionChecker::ApartAlong(const Pose& a, const Pose& b) const {
  // From the middle pose every pose of the motion is within half of its
  // displacement bound (translation and turn angle are both linear in s).
  const double margin = 1e-3 * models_->robot_radius;  // as SweepClear's: far above FCL's tolerances
  const double reach = 0.5 * MaxDisplacement(a, b, models_->robot_radius);
  return models_->walk->Apart(Interpolate(a, b, 0.5), reach + margin);
}

double FclCollisionChecker::Distance(const Pose& pose) const {
  fcl::DistanceRequestd request;
  fcl::DistanceResultd result;
  fcl::distance(models_->robot.get(), ToFcl(pose), models_->environment.get(), fcl::Transform3d::Identity(), request,
                result);
  return std::max(0.0, result.min_distance);
}

FclCollisionChecker::Nearest FclCollisionChecker::NearestTriangles(const Pose& pose) const {
  Nearest out;
  const std::size_t environment_triangles = static_cast<std::size_t>(models_->environment->num_tris);
  const std::size_t robot_triangles = static_cast<std::size_t>(models_->robot->num_tris);
  auto valid = [](intptr_t index, std::size_t n) { return index >= 0 && static_cast<std::size_t>(index) < n; };
  if (InCollision(pose)) {
    // In contact FCL's distance names no pair reliably: the first contact's.
    fcl::CollisionRequestd request(1, true);
    fcl::CollisionResultd result;
    fcl::collide(models_->robot.get(), ToFcl(pose), models_->environment.get(), fcl::Transform3d::Identity(), request,
                 result);
    if (result.numContacts() > 0) {
      const fcl::Contactd& contact = result.getContact(0);
      if (valid(contact.b1, robot_triangles)) out.robot_triangle = static_cast<int>(contact.b1);
      if (valid(contact.b2, environment_triangles)) out.environment_triangle = static_cast<int>(contact.b2);
    }
    return out;
  }
  fcl::DistanceRequestd request;
  fcl::DistanceResultd result;
  fcl::distance(models_->robot.get(), ToFcl(pose), models_->environment.get(), fcl::Transform3d::Identity(), request,
                result);
  out.distance = std::max(0.0, result.min_distance);
  if (valid(result.b1, robot_triangles)) out.robot_triangle = static_cast<int>(result.b1);
  if (valid(result.b2, environment_triangles)) out.environment_triangle = static_cast<int>(result.b2);
  return out;
}

FclCollisionChecker::Closest FclCollisionChecker::ClosestPoints(const Pose& pose) const {
  Closest closest;
  fcl::CollisionRequestd collision_request(1, true);  // one contact, with its position
  fcl::CollisionResultd collision_result;
  fcl::collide(models_->robot.get(), ToFcl(pose), models_->environment.get(), fcl::Transform3d::Identity(),
               collision_request, collision_result);
  if (collision_result.isCollision()) {
    closest.on_robot = closest.on_environment = collision_result.getContact(0).pos;
    return closest;
  }
  fcl::DistanceRequestd request(true);  // nearest points, in world coordinates (FCL >= 0.6)
  fcl::DistanceResultd result;
  fcl::distance(models_->robot.get(), ToFcl(pose), models_->environment.get(), fcl::Transform3d::Identity(), request,
                result);
  closest.distance = std::max(0.0, result.min_distance);
  closest.on_robot = result.nearest_points[0];
  closest.on_environment = result.nearest_points[1];
  return closest;
}

}  // namespace ausbau
