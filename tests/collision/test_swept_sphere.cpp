// collision/swept_sphere.h and what it stands on: segment-triangle distances
// (geometry/closest_point.h) on hand-checked cases and against dense
// sampling, TriangleBvh::AnyWithinSegment against brute force,
// and the proof of a whole motion against FCL on poses along it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "collision/fcl_checker.h"
#include "collision/swept_sphere.h"
#include "core/random.h"
#include "geometry/closest_point.h"
#include "geometry/primitives.h"
#include "geometry/triangle_bvh.h"
#include "test_poses.h"

namespace ausbau {
namespace {

using Eigen::Vector3d;
using testing::PoseAt;

const Vector3d kA(0, 0, 0), kB(2, 0, 0), kC(0, 2, 0);  // a right triangle in z = 0

TEST(SegmentTriangle, HandCheckedCases) {
  // Crossing the interior: 0.
  EXPECT_EQ(SegmentTriangleDistanceSquared({0.5, 0.5, -1}, {0.5, 0.5, 1}, kA, kB, kC), 0.0);
  // Parallel above the interior at height 0.3.
  EXPECT_NEAR(SegmentTriangleDistanceSquared({0.2, 0.2, 0.3}, {0.8, 0.4, 0.3}, kA, kB, kC), 0.09, 1e-15);
  // Ending 0.4 above the interior, pointing away.
  EXPECT_NEAR(SegmentTriangleDistanceSquared({0.5, 0.5, 0.4}, {0.5, 0.5, 3}, kA, kB, kC), 0.16, 1e-15);
  // Passing beside the hypotenuse, in the plane: nearest to the edge x + y = 2.
  EXPECT_NEAR(SegmentTriangleDistanceSquared({2, 1, 0}, {1, 2, 0}, kA, kB, kC), 0.5, 1e-15);
  // Beyond vertex B along x, skew: from (3, 0, 1) to (3, 0, -1): 1 from B.
  EXPECT_NEAR(SegmentTriangleDistanceSquared({3, 0, 1}, {3, 0, -1}, kA, kB, kC), 1.0, 1e-15);
  // A point (degenerate segment) above the interior.
  EXPECT_NEAR(SegmentTriangleDistanceSquared({0.5, 0.5, 2}, {0.5, 0.5, 2}, kA, kB, kC), 4.0, 1e-15);
  // A degenerate triangle (all on the x axis): the segment from (1, 1, -1) to (1, 1, 1) is 1 away.
  EXPECT_NEAR(SegmentTriangleDistanceSquared({1, 1, -1}, {1, 1, 1}, kA, kB, {1, 0, 0}), 1.0, 1e-15);
}

// The smallest distance over a fine sampling of both: an upper bound of the
// true distance, close to it.
double SampledDistance(const Vector3d& p0, const Vector3d& p1, const Vector3d& a, const Vector3d& b,
                       const Vector3d& c) {
  constexpr int kN = 60;
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= kN; ++i) {
    const Vector3d p = p0 + (p1 - p0) * (static_cast<double>(i) / kN);
    for (int j = 0; j <= kN; ++j) {
      for (int k = 0; j + k <= kN; ++k) {
        const Vector3d q = a + (b - a) * (static_cast<double>(j) / kN) + (c - a) * (static_cast<double>(k) / kN);
        best = std::min(best, (p - q).norm());
      }
    }
  }
  return best;
}

TEST(SegmentTriangle, AgreesWithDenseSampling) {
  Random random(11);
  auto point = [&random] { return Vector3d(random.Uniform(-1, 1), random.Uniform(-1, 1), random.Uniform(-1, 1)); };
  for (int trial = 0; trial < 200; ++trial) {
    const Vector3d a = point(), b = point(), c = point(), p0 = point(), p1 = point();
    const double exact = std::sqrt(SegmentTriangleDistanceSquared(p0, p1, a, b, c));
    const double sampled = SampledDistance(p0, p1, a, b, c);
    // Never more than the sampled distance (what a proof may not overstate);
    // and not much less: the sampling's grid is 2/60 wide at most.
    EXPECT_LE(exact, sampled + 1e-12) << "trial " << trial;
    EXPECT_GE(exact, sampled - 0.06) << "trial " << trial;
  }
}

TEST(TriangleBvh, AnyWithinSegmentAgreesWithBruteForce) {
  Random random(5);
  std::vector<Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
  for (int i = 0; i < 300; ++i) {
    const Vector3d corner(random.Uniform(-10, 10), random.Uniform(-10, 10), random.Uniform(-10, 10));
    vertices.push_back(corner);
    vertices.push_back(corner + Vector3d(random.Uniform(-1, 1), random.Uniform(-1, 1), 0));
    vertices.push_back(corner + Vector3d(0, random.Uniform(-1, 1), random.Uniform(-1, 1)));
    triangles.push_back({3 * i, 3 * i + 1, 3 * i + 2});
  }
  const TriangleBvh tree(vertices, triangles);
  int within = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const Vector3d p0(random.Uniform(-12, 12), random.Uniform(-12, 12), random.Uniform(-12, 12));
    const Vector3d p1 = p0 + Vector3d(random.Uniform(-4, 4), random.Uniform(-4, 4), random.Uniform(-4, 4));
    const double radius = random.Uniform(0, 2);
    bool brute = false;
    for (const auto& t : triangles) {
      brute |=
          SegmentTriangleDistanceSquared(p0, p1, vertices[t[0]], vertices[t[1]], vertices[t[2]]) <= radius * radius;
    }
    EXPECT_EQ(tree.AnyWithinSegment(p0, p1, radius), brute) << "trial " << trial;
    within += brute;
  }
  EXPECT_GT(within, 50);  // both answers are exercised
  EXPECT_LT(within, 450);
  EXPECT_FALSE(TriangleBvh().AnyWithinSegment({0, 0, 0}, {1, 1, 1}, 5));
}

TEST(SweptSphere, BoundingSphereHoldsEveryVertex) {
  const TriangleMesh box = MakeBox({1, -1, -2}, {3, 1, 2});
  const BoundingSphere sphere = BoundingSphere::Of(box.vertices);
  EXPECT_TRUE(sphere.centre.isApprox(Vector3d(2, 0, 0)));
  EXPECT_NEAR(sphere.radius, std::sqrt(1 + 1 + 4), 1e-12);
}

// A motion the sweep proves clear is clear at every pose FCL checks along
// it; and motions through open space are proved.
TEST(SweptSphere, ProvedMotionsAreFreeAtEveryPose) {
  // D: a bar off its reference point (so its sphere's centre turns along a
  // bent path); S: a plate with a hole.
  const TriangleMesh robot = MakeBox({0.5, -0.2, -0.2}, {2.5, 0.2, 0.2});
  const TriangleMesh environment = MakePlateWithHole(6, 1, -0.5, 0.5);
  const FclCollisionChecker fcl(robot, environment);
  Random random(3);
  int proved = 0, free_motions = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const Pose a = PoseAt(random.Uniform(-8, 8), random.Uniform(-8, 8), random.Uniform(-8, 8),
                          random.Uniform(-M_PI, M_PI), Vector3d(random.Uniform(-1, 1), random.Uniform(-1, 1), 1));
    const Pose b =
        PoseAt(a.t.x() + random.Uniform(-3, 3), a.t.y() + random.Uniform(-3, 3), a.t.z() + random.Uniform(-3, 3),
               random.Uniform(-M_PI, M_PI), Vector3d(1, random.Uniform(-1, 1), random.Uniform(-1, 1)));
    bool free = true;
    for (int i = 0; i <= 400 && free; ++i) free = !fcl.InCollision(Interpolate(a, b, i / 400.0));
    const bool sweep = fcl.ProveMotion(a, b);
    if (sweep) {
      EXPECT_TRUE(free) << "trial " << trial;
      ++proved;
    }
    free_motions += free;
  }
  EXPECT_GT(proved, 40);  // far from the plate, the sweeps prove motions
  EXPECT_GT(free_motions, proved);
  EXPECT_EQ(fcl.checks(), 400);  // one check each
}

TEST(SweptSphere, ATurnNearTheWallIsNotProved) {
  // A bar turning by 90 degrees about z next to a wall at x = 2.6: the
  // motion is free (no point of the bar is farther than 2.504 from the
  // reference point), but the bound of the turn reaches the wall, so it is
  // not proved (which says nothing about the motion).
  const TriangleMesh robot = MakeBox({0.5, -0.1, -0.1}, {2.5, 0.1, 0.1});
  const TriangleMesh environment = MakeBox({2.6, -10, -10}, {3, 10, 10});
  const FclCollisionChecker fcl(robot, environment);
  const Pose a = PoseAt(0, -2.4, 0, M_PI / 2), b = PoseAt(0, 0, 0, 0);
  EXPECT_FALSE(fcl.InCollision(a));
  EXPECT_FALSE(fcl.InCollision(b));
  EXPECT_FALSE(fcl.ProveMotion(a, b));
  // Far from the wall the same turn is proved.
  EXPECT_TRUE(fcl.ProveMotion(PoseAt(-5, -2.4, 0, M_PI / 2), PoseAt(-5, 0, 0, 0)));
}

}  // namespace
}  // namespace ausbau
