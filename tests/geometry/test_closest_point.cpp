// geometry/closest_point.h: the closest point on a triangle, each Voronoi
// region and the boundaries between them, on hand-computed cases.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "geometry/closest_point.h"

namespace ausbau {
namespace {

// ---------------------------------------------------------------- closest point on a triangle

// The triangle (0,0,0), (1,0,0), (0,1,0): each Voronoi region has a point
// whose answer can be read off. Every variant of the kernel agrees on a
// proper triangle (and here exactly: the numbers are dyadic).
struct ClosestPointCase {
  const char* region;
  Eigen::Vector3d p, expected_point, expected_weights;
};

TEST(ClosestPointOnTriangle, EachVoronoiRegion) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const ClosestPointCase cases[] = {
      {"vertex a", {-1, -1, 0.5}, {0, 0, 0}, {1, 0, 0}},
      {"vertex b", {2, -0.5, -1}, {1, 0, 0}, {0, 1, 0}},
      {"vertex c", {-0.5, 2, 1}, {0, 1, 0}, {0, 0, 1}},
      {"edge ab", {0.5, -1, 0}, {0.5, 0, 0}, {0.5, 0.5, 0}},
      {"edge ac", {-1, 0.25, 3}, {0, 0.25, 0}, {0.75, 0, 0.25}},
      {"edge bc", {1, 1, -2}, {0.5, 0.5, 0}, {0, 0.5, 0.5}},
      {"face", {0.25, 0.25, 2}, {0.25, 0.25, 0}, {0.5, 0.25, 0.25}},
  };
  const DegenerateTriangles policies[] = {DegenerateTriangles::kUnguarded, DegenerateTriangles::kNearestEdgePoint,
                                          DegenerateTriangles::kNearestCorner};
  const FaceWeights roundings[] = {FaceWeights::kTimesReciprocalOfSum, FaceWeights::kDividedBySum};
  for (const ClosestPointCase& test : cases) {
    for (DegenerateTriangles policy : policies) {
      for (FaceWeights rounding : roundings) {
        Eigen::Vector3d weights;
        const Eigen::Vector3d q = ClosestPointOnTriangle(test.p, a, b, c, policy, rounding, &weights);
        EXPECT_EQ(q, test.expected_point) << test.region;
        EXPECT_EQ(weights, test.expected_weights) << test.region;
        EXPECT_EQ(ClosestPointOnTriangle(test.p, a, b, c, policy, rounding), q) << test.region;
      }
    }
  }
}

TEST(ClosestPointOnTriangle, OnTheBoundaryBetweenRegions) {
  const Eigen::Vector3d a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  // On the line that bounds vertex a's region and edge ab's: the vertex.
  EXPECT_EQ(
      ClosestPointOnTriangle({0, -1, 0}, a, b, c, DegenerateTriangles::kUnguarded, FaceWeights::kTimesReciprocalOfSum),
      a);
  // A point of the triangle is its own closest point.
  EXPECT_EQ(ClosestPointOnTriangle({0.5, 0.5, 0}, a, b, c, DegenerateTriangles::kUnguarded,
                                   FaceWeights::kTimesReciprocalOfSum),
            Eigen::Vector3d(0.5, 0.5, 0));
}

TEST(ClosestPointOnTriangle, CoincidentCornersAreGuardedOnlyWhereAsked) {
  // a == b: the closest point falls in edge ab's region, whose division is
  // 0 / 0. Guarded, the edge answers its first corner; unguarded, NaN (a
  // BVH search then never takes the triangle as nearest).
  const Eigen::Vector3d a(0, 0, 0), b(0, 0, 0), c(1, 0, 0), p(0.5, 1, 0);
  EXPECT_EQ(
      ClosestPointOnTriangle(p, a, b, c, DegenerateTriangles::kNearestEdgePoint, FaceWeights::kTimesReciprocalOfSum),
      a);
  EXPECT_TRUE(std::isnan(
      ClosestPointOnTriangle(p, a, b, c, DegenerateTriangles::kUnguarded, FaceWeights::kTimesReciprocalOfSum).x()));
  EXPECT_TRUE(std::isnan(
      ClosestPointOnTriangle(p, a, b, c, DegenerateTriangles::kNearestCorner, FaceWeights::kDividedBySum).x()));
}

}  // namespace
}  // namespace ausbau
