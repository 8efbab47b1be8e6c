// Mapping transforms: relative encodings, 14-bit CC and NRPN, deadzone, curve, invert,
// toggle and momentary buttons, One Euro filter, slew, soft takeover handing over.
#include "input/mapping.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

Event cc(int n, int v, int64_t t = 0) {
  Event e;
  e.kind = ControlKind::MidiCC;
  e.number = uint32_t(n);
  e.value = v;
  e.t_ns = t;
  e.hi = 127;
  return e;
}

Mapping one_handle() {
  Mapping m;
  m.set_handles({"h"}, {Vec2(0, 0)});
  return m;
}

Binding bind(ControlSpec::Kind k, uint32_t number, TargetKind t, double lo = 0, double hi = 100) {
  Binding b;
  b.control.kind = k;
  b.control.number = number;
  b.target = t;
  b.tf.lo = lo;
  b.tf.hi = hi;
  b.tf.takeover = false;
  return b;
}

TEST(Relative, AllFourCcEncodings) {
  EXPECT_EQ(relative_delta(RelativeMode::TwosComplement, 1), 1);
  EXPECT_EQ(relative_delta(RelativeMode::TwosComplement, 127), -1);
  EXPECT_EQ(relative_delta(RelativeMode::TwosComplement, 64), -64);
  EXPECT_EQ(relative_delta(RelativeMode::BinaryOffset, 65), 1);
  EXPECT_EQ(relative_delta(RelativeMode::BinaryOffset, 60), -4);
  EXPECT_EQ(relative_delta(RelativeMode::SignMagnitude, 0x43), -3);
  EXPECT_EQ(relative_delta(RelativeMode::SignMagnitude, 0x03), 3);
  EXPECT_EQ(relative_delta(RelativeMode::SignMagnitudeInv, 0x43), 3);
  EXPECT_EQ(relative_delta(RelativeMode::SignMagnitudeInv, 0x03), -3);
  Mapping m = one_handle();
  Binding b = bind(ControlSpec::CC, 10, TargetKind::HandleX);
  b.tf.relative = RelativeMode::TwosComplement;
  b.tf.step = 0.5;
  m.add_binding(b);
  m.apply(cc(10, 3));
  m.apply(cc(10, 126));
  EXPECT_DOUBLE_EQ(m.goal(0).x(), 0.5);
}

TEST(Absolute, FourteenBitCcAndNrpn) {
  Mapping m = one_handle();
  m.add_binding(bind(ControlSpec::CC14, 7, TargetKind::HandleX, 0, 16383));
  m.add_binding(bind(ControlSpec::NRPN, 300, TargetKind::HandleY, 0, 16383));
  m.apply(cc(7, 0x40));
  m.apply(cc(7 + 32, 0x21));
  EXPECT_DOUBLE_EQ(m.goal(0).x(), (0x40 << 7) | 0x21);
  m.apply(cc(99, 300 >> 7));
  m.apply(cc(98, 300 & 127));
  m.apply(cc(6, 0x10));
  m.apply(cc(38, 0x05));
  EXPECT_DOUBLE_EQ(m.goal(0).y(), (0x10 << 7) | 0x05);
  m.apply(cc(98, 1));  // another parameter: data no longer ours
  m.apply(cc(6, 0x7F));
  EXPECT_DOUBLE_EQ(m.goal(0).y(), (0x10 << 7) | 0x05);
}

TEST(Absolute, DeadzoneCurveInvert) {
  Mapping m = one_handle();
  Binding b = bind(ControlSpec::CC, 1, TargetKind::HandleX, -1, 1);
  b.tf.deadzone = 0.2;
  m.add_binding(b);
  m.apply(cc(1, 70));  // 0.551: inside the 0.4..0.6 deadzone
  EXPECT_DOUBLE_EQ(m.goal(0).x(), 0.0);
  m.apply(cc(1, 127));
  EXPECT_DOUBLE_EQ(m.goal(0).x(), 1.0);
  Mapping m2 = one_handle();
  Binding c = bind(ControlSpec::CC, 1, TargetKind::HandleX, 0, 1);
  c.tf.curve = 2;
  c.tf.invert = true;
  m2.add_binding(c);
  m2.apply(cc(1, 127 / 4));
  const double n = 1 - (127 / 4) / 127.0;
  EXPECT_DOUBLE_EQ(m2.goal(0).x(), n * n);
}

TEST(Buttons, ToggleAndMomentary) {
  Mapping m = one_handle();
  Binding t = bind(ControlSpec::Note, 36, TargetKind::HandleX, 0, 10);
  t.tf.toggle = true;
  m.add_binding(t);
  m.add_binding(bind(ControlSpec::Note, 37, TargetKind::HandleY, 0, 10));
  auto note = [](int n, bool on) {
    Event e;
    e.kind = on ? ControlKind::MidiNoteOn : ControlKind::MidiNoteOff;
    e.number = uint32_t(n);
    e.value = on ? 100 : 0;
    return e;
  };
  m.apply(note(36, true));
  m.apply(note(36, false));
  EXPECT_DOUBLE_EQ(m.goal(0).x(), 10);
  m.apply(note(36, true));
  EXPECT_DOUBLE_EQ(m.goal(0).x(), 0);
  m.apply(note(37, true));
  EXPECT_DOUBLE_EQ(m.goal(0).y(), 10);
  m.apply(note(37, false));
  EXPECT_DOUBLE_EQ(m.goal(0).y(), 0);
}

TEST(Filters, OneEuroSmoothsJitterAndFollowsMotion) {
  OneEuro f;
  f.enabled = true;
  f.min_cutoff = 1.0;
  f.beta = 0.0;
  double lo = 1, hi = 0;
  for (int i = 0; i < 100; ++i) {
    const double out = f.filter(i % 2 ? 0.52 : 0.48, int64_t(i) * 1'000'000);
    if (i >= 80) {
      lo = std::min(lo, out);
      hi = std::max(hi, out);
    }
  }
  EXPECT_LT(hi - lo, 0.04 / 10);  // 1 kHz jitter of 0.04 peak to peak cut more than 10x
  OneEuro g = f;
  g.beta = 50;
  g.reset();
  OneEuro slow = f;
  slow.reset();
  double fast_out = 0, slow_out = 0;
  for (int i = 0; i < 50; ++i) {
    fast_out = g.filter(i / 50.0, int64_t(i) * 1'000'000);
    slow_out = slow.filter(i / 50.0, int64_t(i) * 1'000'000);
  }
  EXPECT_GT(fast_out, slow_out + 0.1);  // beta cuts lag when moving
}

TEST(Slew, LimitsTheSpeedOfATarget) {
  Mapping m = one_handle();
  Binding b = bind(ControlSpec::CC, 1, TargetKind::HandleX, 0, 100);
  b.tf.slew = 50;  // units per second
  m.add_binding(b);
  m.apply(cc(1, 127));
  m.update(0.5);
  EXPECT_DOUBLE_EQ(m.targets()[0].x(), 25.0);
  m.update(0.5);
  EXPECT_DOUBLE_EQ(m.targets()[0].x(), 50.0);
  m.update(10);
  EXPECT_DOUBLE_EQ(m.targets()[0].x(), 100.0);
}

TEST(Takeover, AnotherWriterMakesTheFaderPickUpAgain) {
  Mapping m = one_handle();
  Binding fader = bind(ControlSpec::CC, 1, TargetKind::HandleX, 0, 127);
  fader.tf.takeover = true;
  Binding enc = bind(ControlSpec::CC, 2, TargetKind::HandleX);
  enc.tf.relative = RelativeMode::BinaryOffset;
  enc.tf.step = 1;
  m.add_binding(fader);
  m.add_binding(enc);
  m.apply(cc(1, 0));  // at the target (0): engaged
  m.apply(cc(1, 40));
  EXPECT_DOUBLE_EQ(m.goal(0).x(), 40);
  m.apply(cc(2, 64 + 30));  // the encoder moves it to 70
  EXPECT_DOUBLE_EQ(m.goal(0).x(), 70);
  m.apply(cc(1, 45));  // fader no longer in control: no jump back
  EXPECT_DOUBLE_EQ(m.goal(0).x(), 70);
  m.apply(cc(1, 80));  // crossed 70: picked up
  EXPECT_DOUBLE_EQ(m.goal(0).x(), 80);
  EXPECT_GE(m.stats().takeover_waits, 1u);
}

// Settings are numbers the mapping keeps in range without knowing what they mean (the loop
// reads one as the iteration count, the solver others as its parameters).
TEST(Settings, AControlSetsANamedNumberWithinItsRange) {
  Mapping m = one_handle();
  const int it = m.add_setting({8, 2, 200, true});
  const int w = m.add_setting({1.0, 1e-6, 1e9, false});
  Binding a = bind(ControlSpec::CC, 1, TargetKind::Setting, 2, 12);
  a.index = it;
  m.add_binding(a);
  Binding b = bind(ControlSpec::CC, 2, TargetKind::Setting, -5, 10);
  b.index = w;
  m.add_binding(b);
  EXPECT_FALSE(m.take_settings_changed());
  m.apply(cc(1, 64));
  EXPECT_EQ(m.setting(it), 7.0);  // 2 + 64/127 x 10 = 7.04, rounded: an integer setting
  EXPECT_TRUE(m.take_settings_changed());
  EXPECT_FALSE(m.take_settings_changed());
  m.apply(cc(1, 64));
  EXPECT_FALSE(m.take_settings_changed()) << "the same value is no change";
  m.apply(cc(2, 0));
  EXPECT_EQ(m.setting(w), 1e-6) << "clamped to the setting's own range";
  m.apply(cc(2, 127));
  EXPECT_DOUBLE_EQ(m.setting(w), 10.0);
}

TEST(Settings, EncodersStepIntegerSettingsByOne) {
  Mapping m = one_handle();
  const int it = m.add_setting({8, 2, 10, true});
  Binding b = bind(ControlSpec::Encoder, 1, TargetKind::Setting);
  b.index = it;
  b.tf.relative = RelativeMode::Delta;
  b.tf.step = 0.25;  // ignored for an integer setting: one tick, one iteration
  m.add_binding(b);
  Event e;
  e.kind = ControlKind::EncoderDelta;
  e.number = 1;
  e.value = 1;
  m.apply(e);
  EXPECT_EQ(m.setting(it), 9.0);
  e.value = 5;
  m.apply(e);
  EXPECT_EQ(m.setting(it), 10.0);  // the top of the range
  e.value = -20;
  m.apply(e);
  EXPECT_EQ(m.setting(it), 2.0);
}

}  // namespace
}  // namespace mar
