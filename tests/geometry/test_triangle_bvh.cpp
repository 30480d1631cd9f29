// geometry/triangle_bvh.h: nearest points against brute force, ray crossings.
#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "geometry/closest_point.h"
#include "geometry/mesh.h"
#include "geometry/primitives.h"
#include "geometry/triangle_bvh.h"

namespace ausbau {
namespace {

// ---------------------------------------------------------------- triangle BVH

// A soup of random triangles in the unit cube (seeded: the same on every
// platform).
TriangleMesh RandomTriangleSoup(std::uint64_t seed, int triangles) {
  Random random(seed);
  TriangleMesh mesh;
  for (int t = 0; t < triangles; ++t) {
    const Eigen::Vector3d corner(random.Uniform01(), random.Uniform01(), random.Uniform01());
    for (int k = 0; k < 3; ++k) {
      mesh.vertices.push_back(
          corner + 0.2 * Eigen::Vector3d(random.Uniform(-1, 1), random.Uniform(-1, 1), random.Uniform(-1, 1)));
    }
    mesh.triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  }
  return mesh;
}

TEST(TriangleBvh, NearestPointMatchesBruteForceOnARandomSoup) {
  const TriangleMesh mesh = RandomTriangleSoup(20240611, 500);
  const TriangleBvh bvh(mesh.vertices, mesh.triangles);
  ASSERT_EQ(bvh.TriangleCount(), 500);
  Random random(7);
  for (int q = 0; q < 400; ++q) {
    const Eigen::Vector3d p(random.Uniform(-0.5, 1.5), random.Uniform(-0.5, 1.5), random.Uniform(-0.5, 1.5));
    double best = std::numeric_limits<double>::infinity();
    int best_triangle = -1;
    for (int t = 0; t < static_cast<int>(mesh.triangles.size()); ++t) {
      const auto& tri = mesh.triangles[t];
      const Eigen::Vector3d c =
          ClosestPointOnTriangle(p, mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]],
                                 DegenerateTriangles::kUnguarded, FaceWeights::kTimesReciprocalOfSum);
      const double d2 = (c - p).squaredNorm();
      if (d2 < best) {
        best = d2;
        best_triangle = t;
      }
    }
    const TriangleBvh::Nearest nearest = bvh.NearestPoint(p);
    EXPECT_EQ(nearest.distance_squared, best) << "query " << q;
    EXPECT_EQ(nearest.triangle, best_triangle) << "query " << q;
    EXPECT_EQ((nearest.point - p).squaredNorm(), best) << "query " << q;
    // A hint only starts the bound: the answer is the same.
    const TriangleBvh::Nearest hinted = bvh.NearestPoint(p, (q * 37) % 500);
    EXPECT_EQ(hinted.triangle, nearest.triangle) << "query " << q;
    // Skipping the nearest triangle gives the second nearest.
    const TriangleBvh::Nearest other = bvh.NearestPoint(p, [&](int t) { return t == nearest.triangle; });
    EXPECT_NE(other.triangle, nearest.triangle);
    EXPECT_GE(other.distance_squared, nearest.distance_squared);
  }
}

TEST(TriangleBvh, RayCrossingsOfAClosedBox) {
  const TriangleMesh box = MakeBox({0, 0, 0}, {1, 1, 1});
  const TriangleBvh bvh(box.vertices, box.triangles);
  const Eigen::Vector3d direction = Eigen::Vector3d(0.3, 0.2, 1).normalized();
  EXPECT_EQ(bvh.CountCrossings({0.3, 0.3, 0.5}, direction, 0), 1);  // from inside: out once
  EXPECT_EQ(bvh.CountCrossings({0.3, 0.3, -1}, direction, 0), 2);   // from below: in and out
  EXPECT_EQ(bvh.CountCrossings({0.3, 0.3, 2}, direction, 0), 0);    // from above: away
  EXPECT_EQ(bvh.CountCrossings({0.3, 0.3, -1}, direction, 0, [](int t) { return t < 2; }), 1);  // z = 0 skipped
  EXPECT_EQ(TriangleBvh().CountCrossings({0, 0, 0}, direction, 0), 0);
  EXPECT_EQ(TriangleBvh().NearestPoint({0, 0, 0}).triangle, -1);
}

}  // namespace
}  // namespace ausbau
