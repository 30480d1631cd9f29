// geometry/weld.h: vertex welding, exact and within a tolerance.
#include <gtest/gtest.h>

#include "geometry/weld.h"

namespace ausbau {
namespace {

// ---------------------------------------------------------------- vertex welding

TEST(WeldExactPositions, EqualPositionsShareAnIndexInOrderOfFirstAppearance) {
  const std::vector<Eigen::Vector3d> vertices = {{1, 2, 3},       {0, 0, 0},      {1, 2, 3},
                                                 {-0.0, 0, -0.0}, {0, 0, 1e-300}, {0, 0, 0}};
  EXPECT_EQ(WeldExactPositions(vertices), (std::vector<int>{0, 1, 0, 1, 2, 1}));
  EXPECT_TRUE(WeldExactPositions({}).empty());
}

TEST(WeldWithinTolerance, JustInsideAndJustOutside) {
  const double tolerance = 1.0;
  const std::vector<Eigen::Vector3d> vertices = {
      {0, 0, 0}, {1, 0, 0}, {0, std::nextafter(1.0, 2.0), 0}, {0, 0, -1}, {0.75, -0.75, 0}};
  std::vector<Eigen::Vector3d> welded;
  const std::vector<int> euclidean =
      WeldWithinTolerance(vertices, tolerance, WeldDistance::kEuclidean, Eigen::Vector3d::Zero(), tolerance, &welded);
  // At the tolerance: welded; one step beyond: not; (0.75, -0.75) is 1.06 away.
  EXPECT_EQ(euclidean, (std::vector<int>{0, 0, 1, 0, 2}));
  ASSERT_EQ(welded.size(), 3u);
  EXPECT_EQ(welded[0], vertices[0]);  // the first of a group keeps its position
  EXPECT_EQ(welded[1], vertices[2]);
  EXPECT_EQ(welded[2], vertices[4]);
  // Measured by the largest coordinate difference, (0.75, -0.75) is 0.75 away.
  welded.clear();
  const std::vector<int> largest = WeldWithinTolerance(vertices, tolerance, WeldDistance::kLargestCoordinate,
                                                       Eigen::Vector3d::Zero(), tolerance, &welded);
  EXPECT_EQ(largest, (std::vector<int>{0, 0, 1, 0, 0}));
}

TEST(WeldWithinTolerance, ChainsDoNotPropagate) {
  // Vertices 0.75 apart with a tolerance of 1: each is compared with the
  // groups' first vertices only, so a chain breaks into groups of two.
  std::vector<Eigen::Vector3d> vertices;
  for (int i = 0; i < 5; ++i) vertices.emplace_back(0.75 * i, 0, 0);
  std::vector<Eigen::Vector3d> welded;
  const std::vector<int> map =
      WeldWithinTolerance(vertices, 1.0, WeldDistance::kEuclidean, Eigen::Vector3d(-0.3, 0, 0), 1.0, &welded);
  EXPECT_EQ(map, (std::vector<int>{0, 0, 1, 1, 2}));
  ASSERT_EQ(welded.size(), 3u);
  EXPECT_EQ(welded[1].x(), 1.5);
  EXPECT_EQ(welded[2].x(), 3.0);
}

TEST(WeldWithinTolerance, ZeroToleranceWeldsEqualPositionsOnly) {
  const std::vector<Eigen::Vector3d> vertices = {{0, 0, 0}, {1e-12, 0, 0}, {0, 0, 0}, {5, 5, 5}, {5, 5, 5}};
  std::vector<Eigen::Vector3d> welded;
  EXPECT_EQ(WeldWithinTolerance(vertices, 0.0, WeldDistance::kEuclidean, Eigen::Vector3d::Zero(), 1e-9, &welded),
            (std::vector<int>{0, 1, 0, 2, 2}));
}

}  // namespace
}  // namespace ausbau
