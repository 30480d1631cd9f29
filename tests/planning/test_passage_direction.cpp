// The second try of a trapped extension (planning/passage_direction.h):
// tangents and their inverse, and the shaping by the neighbours' principal
// directions on hand-checkable sets of poses.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "planning/passage_direction.h"

namespace ausbau {
namespace {

Pose At(double x, double y, double z) {
  Pose pose;
  pose.t = Eigen::Vector3d(x, y, z);
  return pose;
}

Metric MetricWithNu(double nu) {
  Metric metric;
  metric.nu = nu;
  return metric;
}

TEST(PassageDirection, TangentIsTheShiftAndTheRotationVector) {
  Pose to = At(3, 4, 0);
  to.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()));
  const PoseTangent tangent = TangentBetween(At(1, 1, 1), to);
  PoseTangent expected;
  expected << 2, 3, -1, 0, 0, 0.5;
  EXPECT_NEAR((tangent - expected).norm(), 0, 1e-12);
  const Pose back = MoveAlong(At(1, 1, 1), tangent);
  EXPECT_NEAR((back.t - to.t).norm(), 0, 1e-12);
  EXPECT_NEAR(Metric::Rotation(back.q, to.q), 0, 1e-7);
}

TEST(PassageDirection, TangentTakesTheShorterWayRound) {
  Pose to = At(0, 0, 0);
  to.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()));
  to.q.coeffs() = -to.q.coeffs();  // the same rotation, the other sign
  EXPECT_NEAR(TangentBetween(At(0, 0, 0), to)(3), 0.3, 1e-12);
}

TEST(PassageDirection, KeepsOnlyWhatPointsAlongAPassage) {
  // Neighbours along x only: a target up and right keeps its x part, scaled
  // back to the original range (sqrt 2), and loses its y part.
  const Metric metric = MetricWithNu(10.0);
  const std::vector<Pose> line = {At(-0.2, 0, 0), At(-0.1, 0, 0), At(0, 0, 0), At(0.1, 0, 0)};
  Pose shaped;
  ASSERT_TRUE(ShapeAlongPassage(metric, At(0, 0, 0), At(1, 1, 0), line, &shaped));
  EXPECT_NEAR(shaped.t.x(), std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(shaped.t.y(), 0, 1e-9);
  EXPECT_NEAR(shaped.t.z(), 0, 1e-9);
  EXPECT_NEAR(Metric::Rotation(shaped.q, Pose{}.q), 0, 1e-9);
}

TEST(PassageDirection, FollowsATurnCoupledWithATranslation) {
  // A screw: 0.1 rad about z with 0.05 along z per neighbour (a tube
  // threading out of a hole). A target that only lifts comes back as the
  // screw, turning 2 rad per unit of lift as the neighbours do.
  const Metric metric = MetricWithNu(1.0);
  std::vector<Pose> screw;
  for (int i = -2; i <= 2; ++i) {
    Pose pose = At(0, 0, 0.05 * i);
    pose.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d::UnitZ()));
    screw.push_back(pose);
  }
  Pose shaped;
  ASSERT_TRUE(ShapeAlongPassage(metric, At(0, 0, 0), At(0, 0, 0.2), screw, &shaped));
  const PoseTangent tangent = TangentBetween(At(0, 0, 0), shaped);
  EXPECT_GT(tangent(2), 0);
  EXPECT_NEAR(tangent(5) / tangent(2), 2.0, 1e-6);
  EXPECT_NEAR(tangent.head<2>().norm() + tangent.segment<2>(3).norm(), 0, 1e-9);
  // The metric's range stays that of the target (0.2): the lift over nu = 1
  // is larger than the turn over 2 pi.
  EXPECT_NEAR(metric.Range(At(0, 0, 0), shaped), 0.2, 1e-9);
}

TEST(PassageDirection, OpenSpaceChangesNothing) {
  // Neighbours spread equally along all six directions in the metric's
  // units (nu = 1: a shift of 0.01 as far as a turn of 0.02 pi).
  const Metric metric = MetricWithNu(1.0);
  std::vector<Pose> spread;
  for (int axis = 0; axis < 6; ++axis) {
    for (const double sign : {-1.0, 1.0}) {
      PoseTangent tangent = PoseTangent::Zero();
      tangent(axis) = 0.01 * sign * (axis < 3 ? 1.0 : 2 * M_PI);
      spread.push_back(MoveAlong(At(0, 0, 0), tangent));
    }
  }
  Pose to = At(0.1, -0.05, 0.02);
  to.q = Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d(1, 2, 3).normalized()));
  Pose shaped;
  ASSERT_TRUE(ShapeAlongPassage(metric, At(0, 0, 0), to, spread, &shaped));
  EXPECT_NEAR((shaped.t - to.t).norm(), 0, 1e-6);
  EXPECT_NEAR(Metric::Rotation(shaped.q, to.q), 0, 1e-6);
}

TEST(PassageDirection, NoShapeWithoutASpreadOrAnythingAlongIt) {
  const Metric metric = MetricWithNu(1.0);
  Pose shaped = At(7, 7, 7);
  // Too few neighbours.
  EXPECT_FALSE(ShapeAlongPassage(metric, At(0, 0, 0), At(1, 0, 0), {At(0, 0, 0), At(0.1, 0, 0)}, &shaped));
  // Neighbours all at one pose.
  EXPECT_FALSE(ShapeAlongPassage(metric, At(0, 0, 0), At(1, 0, 0), {At(0, 0, 0), At(0, 0, 0), At(0, 0, 0)}, &shaped));
  // A target straight across the passage.
  EXPECT_FALSE(
      ShapeAlongPassage(metric, At(0, 0, 0), At(0, 1, 0), {At(-0.1, 0, 0), At(0, 0, 0), At(0.1, 0, 0)}, &shaped));
  EXPECT_EQ(shaped.t, Eigen::Vector3d(7, 7, 7));  // untouched
}

}  // namespace
}  // namespace ausbau
