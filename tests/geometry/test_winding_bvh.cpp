// The winding-number hierarchy (geometry/winding_bvh.h) against the exact
// sum: its error bound, and the classification it decides, on an open shell
// near its surface and near its cut edges.
#include "geometry/winding_bvh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "geometry/primitives.h"

namespace ausbau {
namespace {

// A torus about z (tube radius 13 about the circle of radius 66), in
// `around` x 24 segments: doubly curved, so that no node of the hierarchy is
// flat (a flat node's dipole term is exact to first order, and would not
// put the bound to the test).
TriangleMesh Torus(int around) {
  std::vector<Eigen::Vector2d> profile;
  for (int k = 0; k < 24; ++k) {
    const double angle = 2 * M_PI * k / 24;
    profile.emplace_back(66 + 13 * std::cos(angle), 13 * std::sin(angle));
  }
  return MakeSolidOfRevolution(profile, around);
}

// The triangles whose boxes meet `keep` (as the reach crop keeps S's
// triangles): the rest of a closed shell, open where it was cut.
TriangleMesh CutOpen(const TriangleMesh& mesh, const Aabb& keep) {
  TriangleMesh out;
  out.vertices = mesh.vertices;
  for (const auto& t : mesh.triangles) {
    Aabb box;
    for (int k = 0; k < 3; ++k) box.Extend(mesh.vertices[t[k]]);
    if ((box.max.array() >= keep.min.array()).all() && (box.min.array() <= keep.max.array()).all())
      out.triangles.push_back(t);
  }
  return out;
}

TEST(WindingBvh, TheBoundHoldsAndTheDecidedClassificationIsTheExactSums) {
  // Cut to the region around a part resting on it: a quarter of the ring.
  Aabb keep;
  keep.Extend(Eigen::Vector3d(-40, 30, -20));
  keep.Extend(Eigen::Vector3d(40, 90, 20));
  const TriangleMesh open = CutOpen(Torus(256), keep);
  ASSERT_LT(open.triangles.size(), 256u * 24 * 2 / 3);
  const WindingBvh bvh(open);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0, 1), near(-0.05, 0.05);
  int inside = 0, outside = 0;
  double largest_error = 0;
  for (int n = 0; n < 3000; ++n) {
    // In the tube's cross-section at an angle about z: within 0.05 of its
    // surface (where a part in contact asks), or anywhere in or around it;
    // a third of them near where the crop cut it (x = -40 and 40), where
    // the winding number passes 1/2.
    const double around = n % 3 == 2 ? (n % 2 ? 1.0 : -1.0) * std::acos(40 / 66.0) + 0.1 * (unit(random) - 0.5)
                                     : M_PI / 2 + 1.4 * (unit(random) - 0.5);
    const double section = 2 * M_PI * unit(random);
    const double from_axis = n % 3 == 0 ? 13 + near(random) : 18 * unit(random);
    const double r = 66 + from_axis * std::cos(section);
    const Eigen::Vector3d p(r * std::cos(around), r * std::sin(around), from_axis * std::sin(section));
    const double winding = bvh.WindingNumberExact(p);
    const bool exact = std::abs(winding) > 0.5;
    EXPECT_EQ(bvh.AbsoluteWindingExceeds(p, 0.5), exact) << p.transpose();
    // The bound holds, also for a crude hierarchy (nodes close by summed as
    // dipoles).
    for (const double node_error : {1.0 / 4096, 1.0 / 64, 0.25}) {
      const WindingBvh::Estimate estimate = bvh.EstimateWindingNumber(p, node_error);
      EXPECT_LE(std::abs(estimate.value - winding), estimate.error_bound + 1e-12) << p.transpose();
      largest_error = std::max(largest_error, std::abs(estimate.value - winding));
    }
    (exact ? inside : outside) += 1;
  }
  EXPECT_GT(inside, 300);
  EXPECT_GT(outside, 300);
  EXPECT_GT(largest_error, 1e-4) << "no dipole term was off: the bound was not put to the test";
}

TEST(WindingBvh, AClosedShellsWindingIsDecidedAsOneOrZero) {
  const WindingBvh bvh(Torus(64));
  EXPECT_TRUE(bvh.AbsoluteWindingExceeds({0, 66, 0}, 0.5));    // in the tube
  EXPECT_FALSE(bvh.AbsoluteWindingExceeds({0, 0, 0}, 0.5));    // in the hole
  EXPECT_FALSE(bvh.AbsoluteWindingExceeds({0, 100, 0}, 0.5));  // beside it
  EXPECT_FALSE(bvh.AbsoluteWindingExceeds({0, 66, 0}, 1.5));   // no point is inside twice
}

}  // namespace
}  // namespace ausbau
