// core/: the "did you mean" of unknown names, cancellation, progress.
#include <gtest/gtest.h>

#include "core/cancel.h"
#include "core/log.h"
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

TEST(Cancel, FlagThrowsOnlyWhenRaised) {
  ResetCancel();
  EXPECT_FALSE(CancelRequested());
  EXPECT_NO_THROW(ThrowIfCancelled());
  RequestCancel();
  EXPECT_TRUE(CancelRequested());
  EXPECT_THROW(ThrowIfCancelled(), Cancelled);
  ResetCancel();
  EXPECT_NO_THROW(ThrowIfCancelled());
}

// Progress writes to stderr only at --log-level info and above; silenced,
// a whole run of updates prints nothing (the tests rely on it).
TEST(Progress, SilentBelowInfo) {
  const LogLevel before = GetLogLevel();
  SetLogLevel(LogLevel::kWarn);
  testing::internal::CaptureStderr();
  {
    const ProgressCallback show = ShowProgress("work");
    for (int i = 0; i <= 10; ++i) show(i, 10);
    const ProgressCallback search = ShowSearchProgress("planning", 5, "iterations");
    search(100, 0);
  }
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  SetLogLevel(LogLevel::kInfo);
  testing::internal::CaptureStderr();
  {
    const ProgressCallback show = ShowProgress("work");  // done at once: quiet (shorter than 2 s)
    for (int i = 0; i <= 10; ++i) show(i, 10);
  }
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  testing::internal::CaptureStderr();
  {
    Progress progress("work", 10, Progress::Left::kAtRate, 0);  // no quiet time
    for (int i = 0; i <= 10; ++i) progress.Update(i);
  }
  const std::string log = testing::internal::GetCapturedStderr();  // not a terminal: a line per 10%
  EXPECT_NE(log.find("work 0% ("), std::string::npos) << log;
  EXPECT_NE(log.find("work 50% ("), std::string::npos) << log;
  EXPECT_NE(log.find("work 100% ("), std::string::npos) << log;
  SetLogLevel(before);
}

}  // namespace
}  // namespace ausbau
