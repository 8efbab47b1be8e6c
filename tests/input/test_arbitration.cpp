// Performers with priorities (input/arbitration.h): the higher priority takes a target, the
// lower waits with its value kept; when the holder lets go the target eases down to the base
// with no jump; equal priorities hand over to the latest mover; a mapping's bindings on one
// handle axis from two devices are arbitrated, and one without a stated priority keeps the
// last write as before.
#include "input/arbitration.h"
#include "input/mapping.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mar {
namespace {

constexpr double kDt = 1.0 / 60;

Arbiter two(int base_priority, int top_priority, double hold = 1.0, double handover = 0.5) {
  Arbiter a;
  a.set_sources({{base_priority, hold, handover}, {top_priority, hold, handover}});
  return a;
}

TEST(Arbiter, TheHigherPriorityTakesAndTheLowerWaitsWithItsValueKept) {
  Arbiter a = two(0, 5);
  double now = 0;
  a.write(0, 10, now);
  EXPECT_EQ(a.holder(), 0);
  EXPECT_DOUBLE_EQ(a.value(), 10) << "the first source takes at once: nothing to hand over from";
  a.write(1, 50, now);
  EXPECT_EQ(a.holder(), 1);
  for (int k = 0; k < 45; ++k) a.update(now += kDt, kDt);
  EXPECT_DOUBLE_EQ(a.value(), 50) << "after its hand-over the override is the target";
  a.write(0, 20, now);  // the base performer turns while overridden
  a.update(now += kDt, kDt);
  EXPECT_EQ(a.holder(), 1);
  EXPECT_DOUBLE_EQ(a.value(), 50) << "the lower priority waits";
  EXPECT_DOUBLE_EQ(a.own(0), 20) << "...with its value kept";
}

TEST(Arbiter, WhenTheHolderLetsGoTheTargetEasesDownToTheBaseWithNoJump) {
  Arbiter a = two(0, 5, 1.0, 0.5);
  double now = 0;
  a.write(0, 10, now);
  a.write(1, 90, now);
  for (int k = 0; k < 30; ++k) a.update(now += kDt, kDt);
  a.write(1, 90, now);  // last touched here
  double last = a.value(), largest = 0;
  int handed = -1;
  for (int k = 1; k <= 120; ++k) {
    const double v = a.update(now += kDt, kDt);
    largest = std::max(largest, std::fabs(v - last));
    last = v;
    if (handed < 0 && a.holder() == 0) handed = k;
  }
  ASSERT_GT(handed, 0) << "the base gets the target back";
  EXPECT_NEAR(handed * kDt, 1.0, 2 * kDt) << "after the holder's hold";
  EXPECT_DOUBLE_EQ(a.value(), 10);
  // 80 units over 0.5 s eased in-out: the steepest frame moves 2 * 80 / 30 = 5.3; a jump is 80
  EXPECT_LE(largest, 2.0 * 80 / 30 + 1e-9);
  EXPECT_GT(largest, 0.5 * 80 / 30) << "and it did move";
}

TEST(Arbiter, AHandOverFollowsTheBaseAsItMoves) {
  Arbiter a = two(0, 5, 0.2, 1.0);
  double now = 0;
  a.write(0, 0, now);
  a.write(1, 100, now);
  for (int k = 0; k < 30; ++k) a.update(now += kDt, kDt);  // the override let go at 0.2 s: the hand-over is on
  ASSERT_EQ(a.holder(), 0);
  ASSERT_TRUE(a.handing_over());
  a.write(0, 40, now);  // the base turns its knob during the hand-over
  for (int k = 0; k < 90; ++k) a.update(now += kDt, kDt);
  EXPECT_FALSE(a.handing_over());
  EXPECT_DOUBLE_EQ(a.value(), 40);
}

TEST(Arbiter, EqualPrioritiesGoToTheLatestMoverAndAMovingSourceBeatsAnIdleBase) {
  Arbiter a;
  a.set_sources({{0, 1.0, 0.25}, {3, 1.0, 0.25}, {3, 1.0, 0.25}});
  double now = 0;
  a.write(0, 0, now);
  a.write(1, 30, now);
  a.write(2, 60, now += kDt);
  EXPECT_EQ(a.holder(), 2) << "the latest of two equals";
  // source 2 lets go while source 1 keeps moving: source 1, not the idle base
  for (int k = 0; k < 90; ++k) {
    a.write(1, 30 + k * 0.1, now);
    a.update(now += kDt, kDt);
  }
  EXPECT_EQ(a.holder(), 1);
  EXPECT_NEAR(a.value(), 30 + 89 * 0.1, 1e-9);
}

Event cc_from(uint16_t device, int number, int value) {
  Event e;
  e.source = device;
  e.kind = ControlKind::MidiCC;
  e.number = uint32_t(number);
  e.value = value;
  e.hi = 127;
  return e;
}

Binding knob(uint16_t device, int priority, bool stated) {
  Binding b;
  b.control.kind = ControlSpec::CC;
  b.control.device = device;
  b.control.number = 16;
  b.target = TargetKind::HandleX;
  b.tf.lo = 0;
  b.tf.hi = 127;
  b.tf.priority = {priority, 1.0, 0.5};
  b.tf.has_priority = stated;
  return b;
}

TEST(Arbiter, TwoDevicesOnOneHandleAxisAreArbitratedInTheMapping) {
  Mapping m;
  m.set_handles({"arm"}, {Vec2(0, 0)});
  m.add_binding(knob(0, 0, false));  // the base: no priority of its own, joins when the other states one
  m.add_binding(knob(1, 10, true));
  ASSERT_NE(m.arbiter(0), nullptr);
  EXPECT_EQ(m.arbiter(0), m.arbiter(1));
  m.apply(cc_from(0, 16, 20));
  m.update(kDt);
  EXPECT_DOUBLE_EQ(m.targets()[0].x(), 20) << "no soft takeover under arbitration: the knob sets it";
  EXPECT_EQ(m.holds(0), 1);
  m.apply(cc_from(1, 16, 100));
  for (int k = 0; k < 40; ++k) m.update(kDt);
  EXPECT_DOUBLE_EQ(m.targets()[0].x(), 100);
  EXPECT_EQ(m.holds(0), 0);
  EXPECT_EQ(m.holds(1), 1);
  m.apply(cc_from(0, 16, 30));  // waits
  m.update(kDt);
  EXPECT_DOUBLE_EQ(m.targets()[0].x(), 100);
  for (int k = 0; k < 120; ++k) m.update(kDt);
  EXPECT_DOUBLE_EQ(m.targets()[0].x(), 30) << "the override let go: the base's knob, where it was left";
  EXPECT_EQ(m.holds(0), 1);

  // A lone binding with a priority has nobody to share with: not arbitrated (soft takeover stays).
  Mapping lone;
  lone.set_handles({"arm"}, {Vec2(0, 0)});
  lone.add_binding(knob(0, 5, true));
  EXPECT_EQ(lone.arbiter(0), nullptr);
  EXPECT_EQ(lone.holds(0), -1);

  // Without a stated priority, two bindings on one target are the last write, as before.
  Mapping plain;
  plain.set_handles({"arm"}, {Vec2(0, 0)});
  Binding a = knob(0, 0, false), b = knob(1, 0, false);
  a.tf.takeover = b.tf.takeover = false;
  plain.add_binding(a);
  plain.add_binding(b);
  EXPECT_EQ(plain.arbiter(0), nullptr);
  EXPECT_EQ(plain.holds(0), -1);
  plain.apply(cc_from(1, 16, 100));
  plain.apply(cc_from(0, 16, 20));
  plain.update(kDt);
  EXPECT_DOUBLE_EQ(plain.targets()[0].x(), 20);
}

}  // namespace
}  // namespace mar
