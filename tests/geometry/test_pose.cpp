// geometry/pose.h: interpolation (lerp and slerp along the shorter arc) and
// the bound on how far a vertex moves between two poses, on hand-computed cases.
#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "geometry/pose.h"
#include "test_poses.h"

namespace ausbau {
namespace {

using testing::PoseAt;

TEST(Interpolation, LinearInTranslationAndSlerpInRotation) {
  const Pose a = PoseAt(0, 0, 0), b = PoseAt(2, 4, 6, M_PI / 2, {1, 0, 0});
  const Pose mid = Interpolate(a, b, 0.5);
  EXPECT_TRUE(mid.t.isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_NEAR(RotationAngle(a.q, mid.q), M_PI / 4, 1e-12);
  EXPECT_NEAR(RotationAngle(mid.q, b.q), M_PI / 4, 1e-12);
  EXPECT_TRUE(Interpolate(a, b, 0.0).q.isApprox(a.q));
  EXPECT_TRUE(Interpolate(a, b, 1.0).q.isApprox(b.q));
}

TEST(Interpolation, TakesTheShorterArcWhateverTheSign) {
  const Pose a = PoseAt(0, 0, 0, 0.2);
  Pose b = PoseAt(0, 0, 0, 0.6);
  b.q.coeffs() = -b.q.coeffs();  // same rotation, other hemisphere
  EXPECT_NEAR(RotationAngle(a.q, Interpolate(a, b, 0.5).q), 0.2, 1e-12);
}

TEST(Interpolation, MaxDisplacementBoundsEveryVertexMotion) {
  // A unit-radius point turned by 90 degrees moves sqrt(2) (chord) <= pi/2 (arc).
  const Pose a = PoseAt(0, 0, 0), b = PoseAt(1, 0, 0, M_PI / 2);
  EXPECT_NEAR(MaxDisplacement(a, b, 1.0), 1.0 + M_PI / 2, 1e-12);
  Random random(3);
  for (int i = 0; i < 100; ++i) {
    Eigen::Vector3d p(random.Uniform(-1, 1), random.Uniform(-1, 1), random.Uniform(-1, 1));
    p = p.normalized() * random.Uniform01();
    const double s0 = random.Uniform01(), s1 = random.Uniform01();
    const double moved = (Interpolate(a, b, s1).Apply(p) - Interpolate(a, b, s0).Apply(p)).norm();
    EXPECT_LE(moved, std::abs(s1 - s0) * MaxDisplacement(a, b, 1.0) + 1e-12);
  }
}

}  // namespace
}  // namespace ausbau
