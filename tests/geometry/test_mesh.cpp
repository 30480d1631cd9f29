// geometry/mesh.h: axis-aligned boxes (separation is strict).
#include <gtest/gtest.h>

#include "geometry/mesh.h"

namespace ausbau {
namespace {

TEST(Aabb, SeparationIsStrict) {
  Aabb a, b;
  a.Extend(Eigen::Vector3d(0, 0, 0));
  a.Extend(Eigen::Vector3d(1, 1, 1));
  b.Extend(Eigen::Vector3d(1, 0, 0));
  b.Extend(Eigen::Vector3d(2, 1, 1));
  EXPECT_FALSE(a.SeparatedFrom(b));  // touching faces
  b.min.x() = 1.001;
  EXPECT_TRUE(a.SeparatedFrom(b));
  EXPECT_TRUE(b.SeparatedFrom(a));
}

}  // namespace
}  // namespace ausbau
