// core/log.h: progress lines (silent below --log-level info).
#include <gtest/gtest.h>

#include "core/log.h"

namespace ausbau {
namespace {

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
