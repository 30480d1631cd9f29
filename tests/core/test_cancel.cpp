// core/cancel.h: cancellation (the flag a signal raises).
#include <gtest/gtest.h>

#include "core/cancel.h"

namespace ausbau {
namespace {

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

}  // namespace
}  // namespace ausbau
