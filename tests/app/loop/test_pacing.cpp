#include "app/loop/pacing.h"

#include "devices/device.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

TEST(Pacer, HeadlessFramesAreOnAVirtualClockAndNeverWait) {
  Pacer p(1.0 / 60, false);
  EXPECT_EQ(p.time_of(0), 0);
  EXPECT_EQ(p.time_of(60), 1000000000);
  EXPECT_EQ(p.time_of(90), 1500000000);
  p.start();
  const int64_t t0 = monotonic_ns();
  p.wait_for(1000000);  // would be hours away on a real clock
  EXPECT_LT(monotonic_ns() - t0, int64_t(60) * 1000000000);
}

TEST(Pacer, RealtimeFramesFollowTheMonotonicClockAndWaitForTheirDeadline) {
  Pacer p(0.005, true);
  const int64_t epoch = monotonic_ns();
  p.set_epoch(epoch);
  p.start();
  const int64_t start = monotonic_ns();
  const int64_t t = p.time_of(0);
  EXPECT_GE(t, 0);
  EXPECT_GE(p.time_of(0), t);  // show time moves with the clock, whatever the frame number
  p.wait_for(4);               // 20 ms after start(): never earlier (a busy machine may be later)
  EXPECT_GE(monotonic_ns() - start, 20000000 - 1000);
}

}  // namespace
}  // namespace mar
