#include "planning/scene_goal.h"

#include <cmath>
#include <optional>

#include "collision/fcl_checker.h"
#include "core/format.h"
#include "geometry/placed_box.h"
#include "scene/scene.h"

namespace ausbau {
namespace {

// The gap between two boxes (0 when they overlap or touch).
double Gap(const Aabb& a, const Aabb& b) {
  const Eigen::Vector3d gap = (a.min - b.max).cwiseMax(b.min - a.max).cwiseMax(0.0);
  return gap.norm();
}

std::string Vec(const Eigen::Vector3d& v) { return Fmt("[%.6g, %.6g, %.6g]", v.x(), v.y(), v.z()); }

}  // namespace

struct SceneGoal::Data {
  std::optional<Pose> pose;
  std::optional<GoalCondition> condition;
  TriangleMesh robot;  // D relative to dynamic_origin (scene convention)
  Aabb robot_box;      // its box
  Aabb static_box;
  std::unique_ptr<FclCollisionChecker> fcl;  // only for conditions
};

SceneGoal::SceneGoal(const Scene& scene) : data_(std::make_unique<Data>()) {
  data_->pose = scene.goal;
  data_->condition = scene.goal_condition;
  data_->robot = scene.dynamic_mesh;
  for (auto& v : data_->robot.vertices) v -= scene.dynamic_origin;
  data_->robot_box = data_->robot.Bounds();
  data_->static_box = scene.static_mesh.Bounds();
  if (data_->condition) data_->fcl = std::make_unique<FclCollisionChecker>(data_->robot, scene.static_mesh);
}

SceneGoal::~SceneGoal() = default;
SceneGoal::SceneGoal(SceneGoal&&) noexcept = default;

GoalOutcome SceneGoal::Check(const Pose& pose) const {
  const Data& d = *data_;
  GoalOutcome out;
  if (d.pose) {
    const double dt = (pose.t - d.pose->t).norm();
    const double angle = RotationAngle(pose.q, d.pose->q);
    out.met = dt <= 1e-6 * (1 + d.pose->t.norm()) && angle <= 1e-6;
    if (!out.met) out.why_not = Fmt("D ends %.6g from the goal position and %.6g rad from its rotation", dt, angle);
    return out;
  }
  if (!d.condition) {
    // Exact box of D (its vertices placed), strictly apart from S's.
    Aabb box;
    for (const auto& v : d.robot.vertices) box.Extend(pose.Apply(v));
    out.met = box.SeparatedFrom(d.static_box);
    if (!out.met) out.why_not = "D's AABB still overlaps S's";
    return out;
  }
  const GoalCondition& c = *d.condition;
  if (c.region && !c.region->Contains(pose.t)) {
    out.why_not = "dynamic_origin lies at " + Vec(pose.t) + ", outside the goal region " + Vec(c.region->min) + " .. " +
                  Vec(c.region->max);
    return out;
  }
  if (c.clearance > 0) {
    const double distance = d.fcl->Distance(pose);
    out.met = distance >= c.clearance;
    if (!out.met) out.why_not = Fmt("D is %.6g from S, less than the goal's clearance %.6g", distance, c.clearance);
    return out;
  }
  out.met = !d.fcl->InCollision(pose);
  if (!out.met) out.why_not = "D touches S in the goal region";
  return out;
}

std::string SceneGoal::Describe() const {
  const Data& d = *data_;
  if (d.pose) return "the goal pose";
  if (!d.condition) return "D's AABB clear of S's";
  std::string text;
  if (d.condition->region) {
    text = "dynamic_origin in " + Vec(d.condition->region->min) + " .. " + Vec(d.condition->region->max);
  }
  if (d.condition->clearance > 0) {
    text += (text.empty() ? "" : ", ") + Fmt("D at least %.6g from S", d.condition->clearance);
  } else {
    text += ", D not touching S";
  }
  return text;
}

std::function<bool(const Pose&)> ConditionGoalTest(const Scene& scene, const TriangleMesh& robot,
                                                   const Eigen::Vector3d& offset) {
  if (!scene.goal_condition) return {};
  const GoalCondition condition = *scene.goal_condition;
  const auto fcl = std::make_shared<const FclCollisionChecker>(robot, scene.static_mesh);
  const Aabb robot_box = robot.Bounds();
  const Aabb static_box = scene.static_mesh.Bounds();
  // The planner asks for a hair more than the goal (1e-6 of the clearance, 1e-9 of the region's size inside
  // its faces), so that the rounding of the conversion to the scene convention and of path.csv never turns
  // an end the planner accepted into one the exact check refuses.
  const double clearance = condition.clearance * (1 + 1e-6);
  std::optional<Aabb> region = condition.region;
  if (region) {
    const double inset = 1e-9 * (1 + region->Diagonal() + region->min.cwiseAbs().maxCoeff());
    region->min.array() += inset;
    region->max.array() -= inset;
  }
  return [region, clearance, fcl, robot_box, static_box, offset](const Pose& pose) {
    if (region && !region->Contains(pose.t - pose.q * offset)) return false;
    const double box_gap = Gap(PlacedBox(robot_box, pose), static_box);
    if (clearance > 0) {
      // D lies inside its box, S inside its: the boxes' gap is a lower bound of the distance.
      return box_gap >= clearance || fcl->Distance(pose) >= clearance;
    }
    return box_gap > 0 || !fcl->InCollision(pose);
  };
}

}  // namespace ausbau
