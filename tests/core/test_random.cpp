// core/random.h: the seeded stream (same seed, same numbers).
#include <gtest/gtest.h>

#include "core/random.h"

namespace ausbau {
namespace {

TEST(Random, SameSeedSameStream) {
  Random a(42), b(42), c(43);
  for (int i = 0; i < 10; ++i) {
    const double x = a.Uniform01();
    EXPECT_EQ(x, b.Uniform01());
    EXPECT_GE(x, 0.0);
    EXPECT_LT(x, 1.0);
  }
  EXPECT_NE(Random(42).Uniform01(), c.Uniform01());
  EXPECT_NEAR(a.UniformQuaternion().norm(), 1.0, 1e-12);
}

}  // namespace
}  // namespace ausbau
