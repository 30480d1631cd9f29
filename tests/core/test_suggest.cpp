// core/suggest.h: the "did you mean" of unknown names.
#include <gtest/gtest.h>

#include "core/suggest.h"

namespace ausbau {
namespace {

TEST(ClosestName, TyposSwapsPrefixesAndCase) {
  const std::vector<std::string> flags = {"--time-limit", "--max-iterations", "--seed", "--scene", "--threads"};
  EXPECT_EQ(ClosestName("--time-limt", flags), "--time-limit");     // one deletion
  EXPECT_EQ(ClosestName("--tiem-limit", flags), "--time-limit");    // one swap
  EXPECT_EQ(ClosestName("--Time-Limit", flags), "--time-limit");    // case
  EXPECT_EQ(ClosestName("--max-iter", flags), "--max-iterations");  // a prefix
  EXPECT_EQ(ClosestName("--sed", flags), "--seed");
  EXPECT_EQ(ClosestName("--verbose", flags), "");  // nothing near
  EXPECT_EQ(ClosestName("", flags), "");
  EXPECT_EQ(ClosestName("--seed", flags), "");  // a known name is no typo
  // Ties go to the first: "--scen" is one edit from --scene and --seen.
  EXPECT_EQ(ClosestName("--scen", {"--scene", "--seen"}), "--scene");
  // Short keys allow one edit only.
  EXPECT_EQ(ClosestName("uts", {"units"}), "");
  EXPECT_EQ(ClosestName("unit", {"units"}), "units");
}

}  // namespace
}  // namespace ausbau
