#include "app/loop/pacing.h"
#include "app/loop/late_input.h"

#include "devices/device.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <tuple>

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

namespace mar {
namespace {

TEST(Pacer, ALeadWakesTheFrameThatLongBeforeItsDeadline) {
  Pacer p(0.010, true);
  p.set_epoch(monotonic_ns());
  p.start();
  const int64_t due = p.deadline(3);
  p.wait_for(3, 4000);  // 4 ms early: never before due - 4 ms
  EXPECT_GE(monotonic_ns(), due - 4000000);
  EXPECT_EQ(p.deadline(4) - p.deadline(3), 10000000);
}

// Frame times in us on one clock; a frame `c` us of work read at `deadline - lead`.
struct FrameAt {
  int64_t deadline, read, ready, presented;
};
FrameAt frame_at(int64_t deadline_us, double lead_us, double compute_us) {
  const int64_t read = deadline_us * 1000 - int64_t(lead_us * 1000);
  const int64_t presented = read + int64_t(compute_us * 1000);
  return {deadline_us * 1000, read, presented - 50000 > read ? presented - 50000 : read, presented};
}

TEST(LateInput, OffReadsAtTheDeadlineAndOnWakesThePredictedComputePlusTheMarginBefore) {
  LateInput off;
  off.configure(true, false, 8333, 500);
  EXPECT_EQ(off.lead_us(), 0);
  LateInput on;
  on.configure(true, true, 8333, 500);
  EXPECT_EQ(on.lead_us(), 8333);  // nothing measured yet: read right after the last frame
  for (int k = 1; k <= 10; ++k) {
    const FrameAt f = frame_at(k * 8333, on.lead_us(), 300);
    on.frame(f.deadline, f.read, f.ready, f.presented, -1, true);
  }
  EXPECT_DOUBLE_EQ(on.lead_us(), 300 + 500);
  EXPECT_EQ(on.misses(), 0);
}

TEST(LateInput, TheSlowestOfTheLast64FramesIsThePrediction) {
  LateInput l;
  l.configure(true, true, 8333, 500);
  auto run = [&](int from, int n, double compute) {
    for (int k = from; k < from + n; ++k) {
      const FrameAt f = frame_at(k * 8333, l.lead_us(), compute);
      l.frame(f.deadline, f.read, f.ready, f.presented, -1, true);
    }
  };
  run(1, 10, 300);
  run(11, 1, 2000);  // a slow frame in an 800 us lead: it misses, and is remembered
  EXPECT_EQ(l.misses(), 1);
  EXPECT_DOUBLE_EQ(l.lead_us(), 2000 + l.margin_us());
  run(12, 63, 300);
  EXPECT_DOUBLE_EQ(l.lead_us(), 2000 + l.margin_us());  // still among the last 64
  run(75, 1, 300);
  EXPECT_DOUBLE_EQ(l.lead_us(), 300 + l.margin_us());  // gone; the margin it raised stays a while
  EXPECT_EQ(l.misses(), 1);
}

TEST(LateInput, AMissMakesItMoreCarefulAndQuietFramesRelaxTheMarginBack) {
  LateInput l;
  l.configure(true, true, 8333, 500);
  const FrameAt a = frame_at(8333, 800, 300);
  l.frame(a.deadline, a.read, a.ready, a.presented, -1, true);
  EXPECT_EQ(l.misses(), 0);
  const FrameAt b = frame_at(2 * 8333, l.lead_us(), 1500);  // 1.5 ms of work in a 0.8 ms lead
  l.frame(b.deadline, b.read, b.ready, b.presented, -1, true);
  EXPECT_EQ(l.misses(), 1);
  EXPECT_NEAR(l.margin_us(), 500 + 700, 1);  // grown by what it missed by
  for (int k = 3; k < 3 + 120 * 40; ++k) {
    const FrameAt f = frame_at(k * 8333, l.lead_us(), 300);
    l.frame(f.deadline, f.read, f.ready, f.presented, -1, true);
  }
  EXPECT_EQ(l.misses(), 1);
  EXPECT_NEAR(l.margin_us(), 500, 1);  // back to where it started, never below
  EXPECT_GE(l.margin_us(), 500);
}

TEST(LateInput, TheNewestInputIsShownAtTheDeadlineOrTheTickAfterALateFrame) {
  for (bool on : {false, true}) {
    LateInput l;
    l.configure(true, on, 10000, 500);
    for (int k = 1; k <= 5; ++k) {
      const double lead = on ? 1000 : 0;  // off: read at the deadline, ready after it
      const FrameAt f = frame_at(k * 10000, lead, 300);
      l.frame(f.deadline, f.read, f.ready, f.presented, f.read - 200000, true);  // input 0.2 ms before the read
    }
    nlohmann::json j;
    l.add_stats(j);
    const auto& s = j["late_input"];
    EXPECT_EQ(s["on"], on);
    EXPECT_EQ(s["frames"], 5);
    EXPECT_NEAR(s["device_to_read_us"]["p50"].get<double>(), 200, 1);
    EXPECT_NEAR(s["newest_input_to_ready_us"]["p50"].get<double>(), 450, 1);  // 0.2 ms + 0.3 ms work - 0.05 present
    // on: shown at its deadline 1 ms after the read; off: at the next tick, 10 ms after the read
    EXPECT_NEAR(s["newest_input_to_shown_us"]["p50"].get<double>(), on ? 1200 : 10200, 1);
    EXPECT_EQ(s["missed_deadlines"], 0);  // off: reading when due is the plan, not a miss
  }
}

TEST(LateInput, WarmUpFramesTeachThePredictionButAreNotCounted) {
  LateInput l;
  l.configure(true, true, 8333, 500);
  const FrameAt f = frame_at(8333, 8333, 9000);  // the first frame: slow, late
  l.frame(f.deadline, f.read, f.ready, f.presented, -1, false);
  EXPECT_EQ(l.misses(), 0);
  EXPECT_DOUBLE_EQ(l.margin_us(), 500);
  EXPECT_DOUBLE_EQ(l.lead_us(), 8333);  // 9000 + 500, at most a period
}

// With vsync, present returns at the flip: its wait is not the frame's work (not a miss, not
// in the prediction), and the newest input is estimated to the photon: its age when present
// returned plus half a refresh. Without vsync it says why not; without the display's refresh rate
// it is measured from the intervals between presents.
TEST(LateInput, WithVsyncThePhotonIsEstimatedAndPresentsWaitIsNotWork) {
  LateInput l;
  l.configure(true, true, 16667, 500);
  l.set_display(true, 60);
  const int64_t ms = 1'000'000;
  for (int k = 1; k <= 4; ++k) {
    const int64_t deadline = k * 16667 * 1000, read = deadline - 3 * ms, ready = read + 1 * ms;
    const int64_t presented = deadline + 6 * ms;  // present waited for a flip after the deadline
    l.frame(deadline, read, ready, presented, read - ms, true);
  }
  nlohmann::json j;
  l.add_stats(j);
  const auto& s = j["late_input"];
  EXPECT_EQ(s["missed_deadlines"], 0);
  EXPECT_NEAR(l.lead_us(), 1000 + 500, 1);  // read -> ready, plus the margin
  EXPECT_EQ(s["display"]["vsync"], true);
  EXPECT_EQ(s["display"]["refresh_hz"], 60);
  EXPECT_EQ(s["display"]["refresh_from"], "display");
  // 1 ms before the read, presented 3 + 6 ms after the read: 10 ms, and half of 16.7 ms
  EXPECT_NEAR(s["newest_input_to_photon_us_estimate"]["p50"].get<double>(), 10000 + 8333, 30);
  for (const auto& [vsync, hz, why] : {std::tuple{false, 60, "no vsync"}, std::tuple{true, 0, "not known yet"}}) {
    LateInput m;
    m.configure(true, true, 16667, 500);
    m.set_display(vsync, hz);
    m.frame(16667000, 16000000, 16500000, 16600000, 15000000, true);
    nlohmann::json k;
    m.add_stats(k);
    const auto& e = k["late_input"]["newest_input_to_photon_us_estimate"];
    ASSERT_TRUE(e.is_string()) << e.dump();
    EXPECT_NE(e.get<std::string>().find(why), std::string::npos) << e;
  }
  // No rate from the display: presents every 20 ms (a 50 Hz refresh; two of them late by one).
  LateInput m;
  m.configure(true, true, 20000, 500);
  m.set_display(true, 0);
  for (int k = 1; k <= 30; ++k) {
    const int64_t presented = int64_t(k) * 20 * ms + (k == 7 || k == 19 ? 20 * ms : 0);
    m.frame(presented - 5 * ms, presented - 8 * ms, presented - 7 * ms, presented, presented - 10 * ms, true);
  }
  nlohmann::json k;
  m.add_stats(k);
  EXPECT_EQ(k["late_input"]["display"]["refresh_from"], "present intervals");
  EXPECT_NEAR(k["late_input"]["display"]["refresh_hz"].get<double>(), 50, 1);
  EXPECT_NEAR(k["late_input"]["newest_input_to_photon_us_estimate"]["p50"].get<double>(), 10000 + 10000, 100);
}

}  // namespace
}  // namespace mar
