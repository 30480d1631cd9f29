// FCL collision between two boxes and a peg in a plate with a hole.
#include <gtest/gtest.h>

#include "collision/fcl_checker.h"
#include "geometry/primitives.h"
#include "test_poses.h"

namespace ausbau {
namespace {

using testing::PoseAt;

TEST(FclCollision, TwoBoxes) {
  const FclCollisionChecker checker(MakeBox({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}), MakeBox({-1, -1, -1}, {1, 1, 1}));
  EXPECT_TRUE(checker.InCollision(PoseAt(1.4, 0, 0)));   // overlap 0.1
  EXPECT_FALSE(checker.InCollision(PoseAt(1.6, 0, 0)));  // gap 0.1
  EXPECT_NEAR(checker.Distance(PoseAt(1.6, 0, 0)), 0.1, 1e-9);
  // Turned by 45 degrees the half-diagonal is 0.707: at x = 1.6 it reaches 0.893... no contact
  // until x < 1 + 0.7071.
  EXPECT_TRUE(checker.InCollision(PoseAt(1.65, 0, 0, M_PI / 4)));
  EXPECT_FALSE(checker.InCollision(PoseAt(1.75, 0, 0, M_PI / 4)));
  EXPECT_EQ(checker.checks(), 0);  // InCollision is the raw query; IsValid counts
  EXPECT_TRUE(checker.IsValid(PoseAt(5, 5, 5)));
  EXPECT_FALSE(checker.IsValid(PoseAt(1.4, 0, 0)));
  EXPECT_EQ(checker.checks(), 2);
  EXPECT_EQ(checker.invalid_checks(), 1);
}

TEST(FclCollision, ContainmentIsNotACollisionForFcl) {
  // FCL intersects surfaces only: a small box fully inside a big one is not
  // reported (documented; the FARR inside test will flag it).
  const FclCollisionChecker checker(MakeBox({-0.1, -0.1, -0.1}, {0.1, 0.1, 0.1}), MakeBox({-1, -1, -1}, {1, 1, 1}));
  EXPECT_FALSE(checker.InCollision(PoseAt(0, 0, 0)));
}

TEST(FclCollision, PegThroughPlateWithHole) {
  // Hole half-width 1, peg half-width 0.9: free when centred, touching when shifted.
  const FclCollisionChecker checker(MakeBox({-0.9, -0.9, -3}, {0.9, 0.9, 3}), MakePlateWithHole(6, 1, -0.5, 0.5));
  EXPECT_FALSE(checker.InCollision(PoseAt(0, 0, 0)));
  EXPECT_FALSE(checker.InCollision(PoseAt(0.09, 0, 0)));
  EXPECT_TRUE(checker.InCollision(PoseAt(0.11, 0, 0)));
  EXPECT_TRUE(checker.InCollision(PoseAt(0, 0, 0, 0.2)));  // turned, its corners hit the rim
  EXPECT_FALSE(checker.InCollision(PoseAt(0, 0, 3.6)));    // pulled out
}

}  // namespace
}  // namespace ausbau
