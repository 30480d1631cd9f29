// The scene's goal as a test of a pose of D: what "D is out" or "D is
// there" means for one scene (schemas/scene.md "Goals"). One definition for
// the planners' goal test (MakePlanningProblem sets PlanningProblem's
// goal_test from it) and for the end check of the independent exact check
// (ExactCheckPath, and so the verdict):
//   no goal            D's world AABB strictly separated from S's (the
//                      disassembly default; the planners' conservative box
//                      of D is used while planning, D's exact box at the end)
//   goal {t, q}        the goal pose (1e-6 relative in t, 1e-6 rad)
//   goal {clearance}   the exact distance between D and S (FCL, triangle to
//                      triangle) at least `clearance` scene units
//   goal {region}      dynamic_origin's world position (the scene pose's t)
//                      inside the box, and D not touching S (FCL)
//   both               both
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "geometry/mesh.h"
#include "geometry/pose.h"

namespace ausbau {

struct Scene;
class FclCollisionChecker;

struct GoalOutcome {
  bool met = false;
  std::string why_not;  // one clause ("D is 12.5 from S, less than the goal's clearance 50"); empty when met
};

class SceneGoal {
 public:
  // Builds FCL's models of D and S when the goal needs them (clearance,
  // region); D is taken in the scene convention (shifted by dynamic_origin).
  explicit SceneGoal(const Scene& scene);
  ~SceneGoal();
  SceneGoal(SceneGoal&&) noexcept;

  // Whether D at `pose` (scene convention) meets the goal.
  GoalOutcome Check(const Pose& scene_pose) const;

  // "D's AABB clear of S's", "the goal pose", "at least 50 from S", ...
  std::string Describe() const;

 private:
  struct Data;
  std::unique_ptr<Data> data_;
};

// The goal test of a condition goal (clearance or region) in the planning
// convention, for PlanningProblem::goal_test: `robot` is D relative to the
// reference point, `offset` = reference_point - dynamic_origin (so that the
// scene pose's t = t - R(q) offset). Thread-safe. Boxes decide first where
// they can: D's conservative box at a gap of at least the clearance from S's
// box is far enough without a distance query.
std::function<bool(const Pose&)> ConditionGoalTest(const Scene& scene, const TriangleMesh& robot,
                                                   const Eigen::Vector3d& offset);

}  // namespace ausbau
