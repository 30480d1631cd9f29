// The walk of FCL's trees (collision/fcl_tree_walk.h) against FCL's own
// collide: the same answer on every pose, by hand on boxes and on random
// poses of non-convex solids in and around a plate with holes.
#include <fcl/narrowphase/collision.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "collision/fcl_checker.h"
#include "collision/fcl_tree_walk.h"
#include "core/random.h"
#include "geometry/primitives.h"
#include "test_poses.h"

namespace ausbau {
namespace {

using testing::PoseAt;

bool FclCollide(const FclModel& robot, const Pose& pose, const FclModel& environment) {
  fcl::Transform3d tf = fcl::Transform3d::Identity();
  tf.linear() = pose.q.toRotationMatrix();
  tf.translation() = pose.t;
  fcl::CollisionRequestd request;
  fcl::CollisionResultd result;
  fcl::collide(&robot, tf, &environment, fcl::Transform3d::Identity(), request, result);
  return result.isCollision();
}

TEST(FclTreeWalk, TwoBoxesByHand) {
  const auto robot = BuildFclModel(MakeBox({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}));
  const auto environment = BuildFclModel(MakeBox({-1, -1, -1}, {1, 1, 1}));
  const FclTreeWalk walk(robot, environment);
  EXPECT_TRUE(walk.Collide(PoseAt(1.4, 0, 0)));             // overlap 0.1
  EXPECT_FALSE(walk.Collide(PoseAt(1.6, 0, 0)));            // gap 0.1
  EXPECT_TRUE(walk.Collide(PoseAt(1.65, 0, 0, M_PI / 4)));  // turned: reaches to 1.65 - 0.707
  EXPECT_FALSE(walk.Collide(PoseAt(1.75, 0, 0, M_PI / 4)));
  EXPECT_FALSE(walk.Collide(PoseAt(0, 0, 0)));  // inside: surfaces apart, as FCL
  EXPECT_FALSE(walk.Collide(PoseAt(0, 0, 1e6)));
}

TEST(FclTreeWalk, EmptyMeshesCollideWithNothing) {
  const auto box = BuildFclModel(MakeBox({-1, -1, -1}, {1, 1, 1}));
  const auto empty = BuildFclModel(TriangleMesh{});
  EXPECT_FALSE(FclTreeWalk(empty, box).Collide(PoseAt(0, 0, 0.5)));
  EXPECT_FALSE(FclTreeWalk(box, empty).Collide(PoseAt(0, 0, 0.5)));
}

// An L-shaped bracket (non-convex) against a plate with two holes, at
// random poses around the plate: both answers occur often, and always agree.
TEST(FclTreeWalk, AnswersAsFclsCollideOnRandomPoses) {
  const TriangleMesh bracket = MakePrism({{0, 0}, {3, 0}, {3, 0.4}, {0.4, 0.4}, {0.4, 2}, {0, 2}}, -0.5, 0.5);
  TriangleMesh plate = MakePlateWithRectHole(6, 4, 1, 0.8, -2, 0, -0.3, 0.3);
  plate.Append(MakeSolidOfRevolution({{0, -2}, {0.3, -2}, {0.3, 2}, {0, 2}}, 24));  // a post in the middle
  const auto robot = BuildFclModel(bracket);
  const auto environment = BuildFclModel(plate);
  const FclTreeWalk walk(robot, environment);
  Random random(7);
  int collisions = 0, agreements = 0;
  constexpr int kPoses = 20000;
  for (int k = 0; k < kPoses; ++k) {
    Pose pose;
    pose.t = {random.Uniform(-8, 8), random.Uniform(-6, 6), random.Uniform(-3, 3)};
    const Eigen::Vector4d q(random.Uniform(-1, 1), random.Uniform(-1, 1), random.Uniform(-1, 1), random.Uniform(-1, 1));
    pose.q = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized();
    const bool fcl_answer = FclCollide(*robot, pose, *environment);
    collisions += fcl_answer;
    agreements += walk.Collide(pose) == fcl_answer;
  }
  EXPECT_EQ(agreements, kPoses);
  EXPECT_GT(collisions, kPoses / 10);
  EXPECT_LT(collisions, kPoses * 9 / 10);
}

TEST(FclTreeWalk, ApartByHand) {
  const auto robot = BuildFclModel(MakeBox({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}));
  const auto environment = BuildFclModel(MakeBox({-1, -1, -1}, {1, 1, 1}));
  const FclTreeWalk walk(robot, environment);
  EXPECT_TRUE(walk.Apart(PoseAt(1.6, 0, 0), 0.05));  // gap 0.1
  EXPECT_FALSE(walk.Apart(PoseAt(1.6, 0, 0), 0.15));
  EXPECT_FALSE(walk.Apart(PoseAt(1.4, 0, 0), 0.01));  // overlap
  EXPECT_FALSE(walk.Apart(PoseAt(1.5, 0, 0), 1e-9));  // touching
  // Turned 45 degrees about z: the edge reaches x = 1.8 - 0.7071, a gap of 0.0929.
  EXPECT_TRUE(walk.Apart(PoseAt(1.8, 0, 0, M_PI / 4), 0.09));
  EXPECT_FALSE(walk.Apart(PoseAt(1.8, 0, 0, M_PI / 4), 0.095));
}

// Apart(pose, margin) is FCL's distance > margin, on random poses of the
// bracket around the plate with the post, for margins across three decades.
TEST(FclTreeWalk, ApartAnswersAsFclsDistance) {
  const TriangleMesh bracket = MakePrism({{0, 0}, {3, 0}, {3, 0.4}, {0.4, 0.4}, {0.4, 2}, {0, 2}}, -0.5, 0.5);
  TriangleMesh plate = MakePlateWithRectHole(6, 4, 1, 0.8, -2, 0, -0.3, 0.3);
  plate.Append(MakeSolidOfRevolution({{0, -2}, {0.3, -2}, {0.3, 2}, {0, 2}}, 24));
  const FclCollisionChecker checker(bracket, plate);
  const FclTreeWalk walk(BuildFclModel(bracket), BuildFclModel(plate));
  Random random(8);
  int apart = 0, near = 0;
  for (int k = 0; k < 3000; ++k) {
    Pose pose;
    pose.t = {random.Uniform(-8, 8), random.Uniform(-6, 6), random.Uniform(-3, 3)};
    pose.q =
        Eigen::Quaterniond(random.Uniform(-1, 1), random.Uniform(-1, 1), random.Uniform(-1, 1), random.Uniform(-1, 1))
            .normalized();
    const double margin = std::pow(10.0, random.Uniform(-2, 1));
    const double distance = checker.Distance(pose);
    if (std::abs(distance - margin) < 1e-9) continue;
    const bool expected = distance > margin;
    EXPECT_EQ(walk.Apart(pose, margin), expected) << "distance " << distance << ", margin " << margin;
    apart += expected;
    near += !expected;
  }
  EXPECT_GT(apart, 300);
  EXPECT_GT(near, 300);
}

}  // namespace
}  // namespace ausbau
