// planning/state_space.h: the thesis metric (eq. 2) and range (eq. 3), bounds,
// the two pose conventions and the disassembly goal region, on hand-computed cases.
#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "geometry/primitives.h"
#include "planning/state_space.h"
#include "test_poses.h"

namespace ausbau {
namespace {

using testing::PoseAt;

TEST(Metric, TranslationIsScaledByTheBoundsExtent) {
  Metric metric{10.0};
  EXPECT_DOUBLE_EQ(metric.Translation({0, 0, 0}, {3, 4, 0}), 0.5);
  EXPECT_DOUBLE_EQ(metric.Translation({1, 1, 1}, {1, 1, 1}), 0.0);
}

TEST(Metric, RotationIsHalfAngleOverPi) {
  // A rotation by angle a about any axis: q1.q2 = cos(a/2), d'_q = (a/2)/pi.
  EXPECT_NEAR(Metric::Rotation(PoseAt(0, 0, 0).q, PoseAt(0, 0, 0, M_PI / 2).q), 0.25, 1e-12);
  EXPECT_NEAR(Metric::Rotation(PoseAt(0, 0, 0).q, PoseAt(0, 0, 0, M_PI).q), 0.5, 1e-12);
  // q and -q are the same rotation: distance 0.
  Eigen::Quaterniond q = PoseAt(0, 0, 0, 1.0, {1, 2, 3}).q;
  Eigen::Quaterniond minus_q(-q.w(), -q.x(), -q.y(), -q.z());
  EXPECT_NEAR(Metric::Rotation(q, minus_q), 0.0, 1e-7);
}

TEST(Metric, ConvexCombinationOfTranslationAndRotation) {
  Metric metric{10.0};
  const Pose a = PoseAt(0, 0, 0), b = PoseAt(3, 4, 0, M_PI / 2);
  // d'_t = 0.5, d'_q = 0.25
  EXPECT_NEAR(metric.Distance(a, b, 0.5), 0.375, 1e-12);
  EXPECT_NEAR(metric.Distance(a, b, 0.2), 0.2 * 0.5 + 0.8 * 0.25, 1e-12);
  EXPECT_NEAR(metric.Distance(a, b, 0.583), 0.583 * 0.5 + 0.417 * 0.25, 1e-12);
  EXPECT_NEAR(metric.Distance(b, a, 0.3), metric.Distance(a, b, 0.3), 1e-15);
}

TEST(Metric, RangeIsTheLargerOfTranslationAndRotation) {
  Metric metric{10.0};
  EXPECT_NEAR(metric.Range(PoseAt(0, 0, 0), PoseAt(3, 4, 0, M_PI / 2)), 0.5, 1e-12);
  EXPECT_NEAR(metric.Range(PoseAt(0, 0, 0), PoseAt(1, 0, 0, M_PI)), 0.5, 1e-12);
  EXPECT_NEAR(metric.Range(PoseAt(0, 0, 0), PoseAt(1, 0, 0, M_PI / 2)), 0.25, 1e-12);
}

PlanningProblem BoxProblem() {
  PlanningProblem problem;
  problem.robot = MakeBox({-1, -0.5, -0.5}, {1, 0.5, 0.5});
  problem.environment = MakeBox({-2, -2, -2}, {2, 2, 2});
  problem.robot_local_box = problem.robot.Bounds();
  problem.environment_box = problem.environment.Bounds();
  problem.bounds.min = {-10, -10, -10};
  problem.bounds.max = {10, 10, 10};
  problem.metric.nu = problem.bounds.Diagonal();
  return problem;
}

TEST(GoalRegion, SeparatedBoundingBoxes) {
  const PlanningProblem problem = BoxProblem();
  EXPECT_FALSE(problem.InGoalRegion(PoseAt(0, 0, 0)));
  EXPECT_FALSE(problem.InGoalRegion(PoseAt(3.0, 0, 0)));  // robot spans x in [2, 4]: touches
  EXPECT_TRUE(problem.InGoalRegion(PoseAt(3.01, 0, 0)));
  // Turned by 90 degrees about z the robot is 1 wide in x: x in [2.01, 3.01].
  EXPECT_TRUE(problem.InGoalRegion(PoseAt(2.51, 0, 0, M_PI / 2)));
  EXPECT_FALSE(problem.InGoalRegion(PoseAt(2.49, 0, 0, M_PI / 2)));
}

TEST(GoalRegion, RobotBoxIsConservative) {
  const PlanningProblem problem = BoxProblem();
  Random random(7);
  for (int i = 0; i < 200; ++i) {
    const Pose pose = problem.SampleUniform(random);
    const Aabb box = problem.RobotBoxAt(pose);
    for (const auto& v : problem.robot.vertices) {
      EXPECT_TRUE((pose.Apply(v).array() >= box.min.array() - 1e-9).all());
      EXPECT_TRUE((pose.Apply(v).array() <= box.max.array() + 1e-9).all());
    }
  }
}

TEST(StateSpace, SceneAndPlanningConventionsRoundTrip) {
  PlanningProblem problem = BoxProblem();
  problem.reference_point = {5, 6, 7};
  problem.dynamic_origin = {0, 0, 0};
  const Pose scene_pose = PoseAt(1, 2, 3, 0.7, {1, 1, 0});
  const Pose planning = problem.SceneToPlanning(scene_pose);
  // The same mesh point lands in the same place in both conventions.
  const Eigen::Vector3d x(1.5, -2, 0.25);
  EXPECT_TRUE((scene_pose.q * (x - problem.dynamic_origin) + scene_pose.t)
                  .isApprox(planning.q * (x - problem.reference_point) + planning.t));
  const Pose back = problem.PlanningToScene(planning);
  EXPECT_TRUE(back.t.isApprox(scene_pose.t));
}

TEST(StateSpace, UniformSamplesStayInBounds) {
  PlanningProblem problem = BoxProblem();
  problem.bounded_point = {1, 0, 0};
  Random random(11);
  for (int i = 0; i < 1000; ++i) EXPECT_TRUE(problem.InBounds(problem.SampleUniform(random)));
}

// How long a stretch of a translation is proved at once: doubled while
// proved, halved when not; after a stretch not proved, kept at the length
// proved until that many proofs in a row, then doubled again.
TEST(StretchLength, DoublesWhileProvedAndWaitsAfterAFailure) {
  StretchLength stretch(8.0);
  EXPECT_EQ(stretch.next(), 8.0);
  stretch.Proved(3.0);  // the motion's end came first: doubled from there
  EXPECT_EQ(stretch.next(), 6.0);
  stretch.NotProved(6.0);
  EXPECT_EQ(stretch.next(), 3.0);
  stretch.NotProved(3.0);
  EXPECT_EQ(stretch.next(), 1.5);
  for (int k = 1; k < StretchLength::kProofsBeforeGrowing; ++k) {
    stretch.Proved(1.5);
    EXPECT_EQ(stretch.next(), 1.5) << k;
  }
  stretch.Proved(1.5);
  EXPECT_EQ(stretch.next(), 3.0);
  stretch.Proved(3.0);  // still in a row: doubled at once
  EXPECT_EQ(stretch.next(), 6.0);
  stretch.NotProved(6.0);
  stretch.Proved(3.0);
  EXPECT_EQ(stretch.next(), 3.0);  // the count starts again
}

}  // namespace
}  // namespace ausbau
