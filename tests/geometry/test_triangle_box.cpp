// geometry/triangle_box.h: the triangle/box overlap test, each separating axis.
#include <gtest/gtest.h>

#include "geometry/triangle_box.h"

namespace ausbau {
namespace {

// ---------------------------------------------------------------- triangle against box

// The box [-1, 1]^3 with each rounding (a cube, so both apply).
bool OverlapsUnitBox(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                     SatRounding rounding) {
  return TriangleOverlapsBox(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), a, b, c, rounding);
}

TEST(TriangleOverlapsBox, EachSeparatingAxisType) {
  for (SatRounding rounding : {SatRounding::kPerAxisHalfExtent, SatRounding::kCubeHalfSize}) {
    // Inside, and crossing the box.
    EXPECT_TRUE(OverlapsUnitBox({-0.5, 0, 0}, {0.5, 0, 0}, {0, 0.5, 0.2}, rounding));
    EXPECT_TRUE(OverlapsUnitBox({-5, -5, 0}, {5, -5, 0}, {0, 5, 0}, rounding));
    // A box face normal: all of the triangle beyond x = 1; touching it counts.
    EXPECT_FALSE(OverlapsUnitBox({1.5, 0, 0}, {2, 1, 0}, {2, 0, 1}, rounding));
    EXPECT_TRUE(OverlapsUnitBox({1, 0, 0}, {2, 1, 0}, {2, 0, 1}, rounding));
    // The triangle's normal: the plane x + y + z = 3.5 passes the corner
    // (1, 1, 1) (sum 3) while the triangle's box holds the whole cube's
    // extent on every axis and no edge axis separates.
    EXPECT_FALSE(OverlapsUnitBox({3.5, 0, 0}, {0, 3.5, 0}, {0, 0, 3.5}, rounding));
    EXPECT_TRUE(OverlapsUnitBox({2.9, 0, 0}, {0, 2.9, 0}, {0, 0, 2.9}, rounding));
    EXPECT_TRUE(OverlapsUnitBox({3, 0, 0}, {0, 3, 0}, {0, 0, 3}, rounding));  // touches the corner
    // An edge cross product: edge (2.2, 0, 0) -> (0, 2.2, 0) passes the box's
    // z edge at x = y = 1 outside; on axis e_z x edge = (-2.2, -2.2, 0) the
    // triangle projects to [-13.2, -4.84] and the box to [-4.4, 4.4]. The
    // face normals and the triangle's normal do not separate them.
    EXPECT_FALSE(OverlapsUnitBox({2.2, 0, 0}, {0, 2.2, 0}, {3, 3, 5}, rounding));
    EXPECT_TRUE(OverlapsUnitBox({1.8, 0, 0}, {0, 1.8, 0}, {3, 3, 5}, rounding));
  }
}

TEST(TriangleOverlapsBox, BoxAwayFromTheOriginWithUnequalHalfExtents) {
  const Eigen::Vector3d center(10, 20, 30), half(1, 2, 3);
  const auto at = [&](double x, double y, double z) { return Eigen::Vector3d(center + Eigen::Vector3d(x, y, z)); };
  const SatRounding rounding = SatRounding::kPerAxisHalfExtent;
  EXPECT_TRUE(TriangleOverlapsBox(center, half, at(0, 1.9, 0), at(0.5, 1.9, 0), at(0, 1.9, 0.5), rounding));
  EXPECT_FALSE(TriangleOverlapsBox(center, half, at(0, 2.1, 0), at(0.5, 2.1, 0), at(0, 2.1, 0.5), rounding));
  EXPECT_TRUE(TriangleOverlapsBox(center, half, at(0, 0, 2.9), at(0.5, 0, 2.9), at(0, 0.5, 2.9), rounding));
  EXPECT_FALSE(TriangleOverlapsBox(center, half, at(0, 0, 3.1), at(0.5, 0, 3.1), at(0, 0.5, 3.1), rounding));
}

}  // namespace
}  // namespace ausbau
