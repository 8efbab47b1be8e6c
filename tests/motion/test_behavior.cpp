// Idle behaviours: blinks at random intervals that are the same for the same seed, within the
// jitter of their mean and shut for their hold; breathing with its period and depth; looking
// about within its range, smoothly; all paused while a performer writes the target and back
// `resume` seconds later; no allocation.
#include "alloc_counter.h"
#include "motion/behavior.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace mar {
namespace {

constexpr double kDt = 1.0 / 60;

std::vector<double> blink_starts(uint64_t seed, double seconds, double mean = 4, double jitter = 0.5) {
  BehaviorSpec s;
  s.kind = BehaviorSpec::Blink;
  s.mean = mean;
  s.jitter = jitter;
  s.seed = seed;
  Behavior b(s);
  std::vector<double> out;
  bool was = false;
  for (int f = 1; f <= int(seconds * 60); ++f) {
    b.step(kDt, false);
    if (b.on() && !was) out.push_back(f * kDt);
    was = b.on();
  }
  return out;
}

TEST(Behavior, BlinksAreTheSameForTheSameSeedAndWithinTheJitter) {
  const auto a = blink_starts(7, 600), b = blink_starts(7, 600), c = blink_starts(8, 600);
  EXPECT_EQ(a, b) << "the same seed, the same blinks";
  EXPECT_NE(a, c);
  ASSERT_GT(a.size(), 100u);
  double sum = 0, lo = 1e9, hi = 0;
  for (size_t i = 1; i < a.size(); ++i) {
    const double d = a[i] - a[i - 1];
    sum += d;
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  const double mean = sum / double(a.size() - 1);
  std::cout << a.size() << " blinks in 10 minutes, every " << mean << " s on average (" << lo << " to " << hi << ")" << std::endl;
  EXPECT_NEAR(mean, 4.0, 0.2);
  EXPECT_GE(lo, 4 * 0.5 - 2 * kDt);
  EXPECT_LE(hi, 4 * 1.5 + 2 * kDt);
}

TEST(Behavior, ABlinkStaysShutForItsHold) {
  BehaviorSpec s;
  s.kind = BehaviorSpec::Blink;
  s.mean = 1;
  s.hold = 0.2;
  Behavior b(s);
  int shut = 0, blinks_seen = 0;
  bool was = false;
  for (int f = 0; f < 600; ++f) {
    b.step(kDt, false);
    shut += b.on();
    blinks_seen += b.on() && !was;
    was = b.on();
  }
  EXPECT_EQ(blinks_seen, b.blinks());
  EXPECT_NEAR(double(shut) / blinks_seen, 0.2 * 60, 1.5) << "frames shut a blink";
}

TEST(Behavior, BreathingHasItsPeriodAndDepth) {
  BehaviorSpec s;
  s.kind = BehaviorSpec::Breathe;
  s.period = 4;
  s.depth = {0, -3};
  s.amount = 0.5;
  Behavior b(s);
  double top = 0, top_value = 0;
  for (int f = 1; f <= 60 * 4; ++f) {
    b.step(kDt, false);
    if (f == 120) {  // half a breath: the top
      top = b.offset().y();
      top_value = b.value();
    }
  }
  EXPECT_NEAR(top, -3, 1e-9);
  EXPECT_NEAR(top_value, 0.5, 1e-9);
  EXPECT_NEAR(b.offset().y(), 0, 1e-9) << "a whole breath: back where it started";
}

TEST(Behavior, LookingStaysInItsRangeSmoothly) {
  BehaviorSpec s;
  s.kind = BehaviorSpec::Look;
  s.range = {8, 4};
  s.speed = 0.2;
  Behavior b(s);
  Vec2 last = Vec2::Zero();
  double step = 0, reach = 0;
  for (int f = 0; f < 60 * 120; ++f) {
    b.step(kDt, false);
    const Vec2 o = b.offset();
    ASSERT_LE(std::abs(o.x()), 8 + 1e-9);
    ASSERT_LE(std::abs(o.y()), 4 + 1e-9);
    if (f > 0) step = std::max(step, (o - last).norm());
    reach = std::max(reach, std::abs(o.x()));
    last = o;
  }
  EXPECT_LT(step, 0.05 * 8) << "smooth: a frame moves it by under 5% of its range";
  EXPECT_GT(reach, 4) << "and it does look about";
}

TEST(Behavior, APerformerPausesItAndItComesBackAfterResume) {
  BehaviorSpec s;
  s.kind = BehaviorSpec::Look;
  s.range = {8, 4};
  s.resume = 2;
  s.fade = 0.5;
  Behavior b(s);
  for (int f = 0; f < 60; ++f) b.step(kDt, false);
  EXPECT_DOUBLE_EQ(b.weight(), 1);
  b.step(kDt, true);  // a control wrote the target
  EXPECT_DOUBLE_EQ(b.weight(), 0);
  EXPECT_EQ(b.offset(), Vec2::Zero());
  for (int f = 0; f < 119; ++f) b.step(kDt, false);  // 119 frames: still inside resume
  EXPECT_DOUBLE_EQ(b.weight(), 0);
  for (int f = 0; f < 15; ++f) b.step(kDt, false);
  EXPECT_GT(b.weight(), 0);
  EXPECT_LT(b.weight(), 1) << "fading back in";
  for (int f = 0; f < 30; ++f) b.step(kDt, false);
  EXPECT_DOUBLE_EQ(b.weight(), 1);
  // A paused blink does not blink.
  BehaviorSpec k;
  k.kind = BehaviorSpec::Blink;
  k.mean = 0.5;
  Behavior blink(k);
  const long allocs = test::allocation_count();
  for (int f = 0; f < 600; ++f) blink.step(kDt, true);
  EXPECT_EQ(blink.blinks(), 0);
  for (int f = 0; f < 600; ++f) blink.step(kDt, false);
  EXPECT_GT(blink.blinks(), 5);
  EXPECT_EQ(test::allocation_count() - allocs, 0) << "step allocates nothing";
}

}  // namespace
}  // namespace mar
