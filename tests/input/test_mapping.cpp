// Mapping transforms: relative encodings, 14-bit CC and NRPN, deadzone, curve, invert,
// toggle and momentary buttons, One Euro filter, slew, soft takeover handing over, swap sets
// and triggers, timed pose eases and returns.
#include "input/mapping.h"
#include "input/midi.h"

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

// Velocity and pressure as continuous controls, from the MIDI bytes a controller sends.
TEST(Absolute, NoteVelocityAftertouchAndPolyPressure) {
  Mapping m;
  m.set_handles({"a", "b", "c"}, {Vec2(0, 0), Vec2(0, 0), Vec2(0, 0)});
  Binding v = bind(ControlSpec::NoteVelocity, 60, TargetKind::HandleX, 0, 127);
  v.index = 0;
  Binding at = bind(ControlSpec::Aftertouch, 0, TargetKind::HandleX, 0, 127);
  at.index = 1;
  at.control.channel = 1;  // channel 2 only
  Binding pp = bind(ControlSpec::PolyPressure, 61, TargetKind::HandleX, 0, 127);
  pp.index = 2;
  m.add_binding(v);
  m.add_binding(at);
  m.add_binding(pp);
  auto send = [&](std::initializer_list<uint8_t> bytes) {
    MidiStreamDecoder p;
    int n = 0;
    const std::vector<uint8_t> raw(bytes);
    p.feed(raw, [&](const MidiMessage& msg) {
      Event e;
      if (midi_to_event(msg, 0, 0, e)) n += m.apply(e);
    });
    return n;
  };
  EXPECT_EQ(send({0x90, 60, 100}), 1);  // note 60 on, velocity 100
  EXPECT_DOUBLE_EQ(m.goal(0).x(), 100);
  EXPECT_EQ(send({0x90, 62, 90}), 0) << "another note";
  EXPECT_DOUBLE_EQ(m.goal(0).x(), 100);
  EXPECT_EQ(send({0x80, 60, 40}), 1);  // its note-off: back to 0
  EXPECT_DOUBLE_EQ(m.goal(0).x(), 0);
  EXPECT_EQ(send({0x90, 60, 1}), 1);
  EXPECT_DOUBLE_EQ(m.goal(0).x(), 1);
  EXPECT_EQ(send({0x90, 60, 0}), 1) << "note-on with velocity 0 is a note-off";
  EXPECT_DOUBLE_EQ(m.goal(0).x(), 0);
  EXPECT_EQ(send({0xD0, 80}), 0) << "aftertouch on channel 1: not ours";
  EXPECT_EQ(send({0xD1, 80}), 1);
  EXPECT_DOUBLE_EQ(m.goal(1).x(), 80);
  EXPECT_EQ(send({0xA0, 61, 33}), 1);
  EXPECT_DOUBLE_EQ(m.goal(2).x(), 33);
  EXPECT_EQ(send({0xA0, 62, 99}), 0) << "another note's pressure";
  EXPECT_DOUBLE_EQ(m.goal(2).x(), 33);
}

// MIDI clock's beat and bar phases (input/midi_clock.h) drive targets as continuous controls, and
// press a button target for the first quarter of each beat.
TEST(Absolute, BeatAndBarPhases) {
  Mapping m;
  m.set_handles({"a", "b"}, {Vec2(0, 0), Vec2(0, 0)});
  Binding beat = bind(ControlSpec::Beat, 0, TargetKind::HandleX, 0, 100);
  Binding bar = bind(ControlSpec::Bar, 0, TargetKind::HandleX, 0, 100);
  bar.index = 1;
  m.add_binding(beat);
  m.add_binding(bar);
  auto phase = [](uint32_t which, double v) {
    Event e;
    e.kind = ControlKind::ClockPhase;
    e.number = which;
    e.lo = 0;
    e.hi = kClockPhaseMax;
    e.value = int32_t(v * kClockPhaseMax);
    return e;
  };
  EXPECT_TRUE(m.apply(phase(kClockBeat, 0.25)));
  EXPECT_TRUE(m.apply(phase(kClockBar, 0.5625)));
  EXPECT_NEAR(m.goal(0).x(), 25, 1e-9);
  EXPECT_NEAR(m.goal(1).x(), 56.25, 1e-9);
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

namespace mar {
namespace {

Event note_event(int n, bool on) {
  Event e;
  e.kind = on ? ControlKind::MidiNoteOn : ControlKind::MidiNoteOff;
  e.number = uint32_t(n);
  e.value = on ? 100 : 0;
  return e;
}

Event hid_value(uint32_t usage, int v, int lo, int hi) {
  Event e;
  e.kind = ControlKind::HidValue;
  e.number = usage;
  e.value = v;
  e.lo = lo;
  e.hi = hi;
  return e;
}

Event gpio(int n, bool down) {
  Event e;
  e.kind = ControlKind::Button;
  e.number = uint32_t(n);
  e.value = down ? 1 : 0;
  return e;
}

// A mouth swap set of three members and two triggers, pressed from a note, a CC past its
// threshold, a HID button, a GPIO button and an OSC value; latched and momentary.
TEST(Swaps, NotesCcsAndButtonsSwapMembersAndFireTriggers) {
  Mapping m = one_handle();
  m.set_swaps({3}, {0}, 2);
  Binding a = bind(ControlSpec::Note, 60, TargetKind::Swap);  // latch (a show's default for swaps)
  a.member = 1;
  a.tf.toggle = true;
  m.add_binding(a);
  Binding o = bind(ControlSpec::CC, 20, TargetKind::Swap);  // momentary, from a CC at a low threshold
  o.member = 2;
  o.tf.threshold = 0.25;
  m.add_binding(o);
  m.add_binding(bind(ControlSpec::Hid, 0x090001, TargetKind::Trigger));  // trigger 0, momentary
  Binding latch = bind(ControlSpec::GpioButton, 4, TargetKind::Trigger);
  latch.index = 1;
  latch.tf.toggle = true;
  m.add_binding(latch);
  Binding osc = bind(ControlSpec::Hid, 0xFF000000u, TargetKind::Swap);  // an OSC address as the show numbers it
  osc.member = 0;
  m.add_binding(osc);

  EXPECT_EQ(m.swap_member(0), 0);
  EXPECT_FALSE(m.take_shown_changed());
  m.apply(note_event(60, true));
  m.apply(note_event(60, false));
  EXPECT_EQ(m.swap_member(0), 1);  // latched: stays after the release
  EXPECT_TRUE(m.take_shown_changed());
  m.apply(cc(20, 20));  // below 0.25 of 127: not pressed
  EXPECT_EQ(m.swap_member(0), 1);
  m.apply(cc(20, 40));
  EXPECT_EQ(m.swap_member(0), 2);
  m.apply(cc(20, 90));  // still held: no new press
  m.apply(cc(20, 0));   // released: back to the member before the press
  EXPECT_EQ(m.swap_member(0), 1);
  m.apply(hid_value(0xFF000000u, 800, 0, 1000));  // OSC 0.8 presses member 0
  EXPECT_EQ(m.swap_member(0), 0);

  m.apply(hid_value(0x090001, 1, 0, 1));
  EXPECT_TRUE(m.trigger_on(0));
  m.apply(hid_value(0x090001, 0, 0, 1));
  EXPECT_FALSE(m.trigger_on(0));
  m.apply(gpio(4, true));
  m.apply(gpio(4, false));
  EXPECT_TRUE(m.trigger_on(1));  // toggled on, stays
  m.apply(gpio(4, true));
  EXPECT_FALSE(m.trigger_on(1));
  EXPECT_TRUE(m.take_shown_changed());
  EXPECT_FALSE(m.take_shown_changed());
}

// A group that follows a handle goes where that handle goes, then turns: an arm's knob swings
// it about the shoulder the body's fader has moved, not about where the shoulder was drawn.
TEST(Groups, AGroupThatFollowsAHandleTurnsAboutThePivotThatHandleMoved) {
  for (const bool follows : {false, true}) {
    Mapping m;
    m.set_handles({"body", "hand"}, {Vec2(0, 0), Vec2(100, 0)});
    RotationGroup g;
    g.name = "arm";
    g.handles = {1};
    g.pivot = Vec2(50, 0);
    g.follow = follows ? 0 : -1;
    m.add_group(g);
    Binding fader = bind(ControlSpec::CC, 10, TargetKind::HandleX, 0, 100);
    fader.index = 0;
    m.add_binding(fader);
    m.add_binding(bind(ControlSpec::CC, 16, TargetKind::Rotate, -90, 90));
    m.apply(cc(10, 127));  // the body 100 to the right
    m.update(1.0 / 60);
    EXPECT_NEAR(m.targets()[0].x(), 100, 1e-9);
    EXPECT_NEAR(m.targets()[1].x(), follows ? 200 : 100, 1e-9) << "the hand goes with the body only when its group follows it";
    m.apply(cc(16, 127));  // +90 degrees
    m.update(1.0 / 60);
    const Vec2 pivot = follows ? Vec2(150, 0) : Vec2(50, 0);
    EXPECT_NEAR((m.pivots()[0] - pivot).norm(), 0, 1e-9);
    EXPECT_NEAR((m.targets()[1] - (pivot + Vec2(0, 50))).norm(), 0, 1e-9) << "turned about the pivot where it is now";
    EXPECT_NEAR(m.targets()[0].x(), 100, 1e-9) << "the body itself does not turn";
  }
}

// A pose recalled after a knob turned a group: the group lets go of its turn, its handle
// starts from where the turn put it (no jump) and eases to the pose's position.
TEST(Poses, APoseBringsBackAHandleAKnobTurned) {
  Mapping m;
  m.set_handles({"hand"}, {Vec2(100, 0)});
  RotationGroup g;
  g.name = "arm";
  g.handles = {0};
  g.pivot = Vec2(0, 0);
  m.add_group(g);
  Binding knob = bind(ControlSpec::CC, 16, TargetKind::Rotate, -90, 90);
  m.add_binding(knob);
  Pose p;
  p.name = "rest";
  p.positions = {Vec2(100, 0)};
  m.add_pose(p);
  Binding b = bind(ControlSpec::Note, 36, TargetKind::Pose);
  b.tf.transition = 0.5;
  m.add_binding(b);
  m.apply(cc(16, 127));  // +90 degrees: the hand below the pivot (y down)
  m.update(1.0 / 60);
  EXPECT_NEAR(m.targets()[0].x(), 0, 1e-9);
  EXPECT_NEAR(m.targets()[0].y(), 100, 1e-9);
  m.apply(note_event(36, true));
  m.update(1.0 / 60);
  EXPECT_NEAR(m.targets()[0].y(), 100, 1.0) << "no jump: it starts where the turn left it";
  for (int f = 0; f < 40; ++f) m.update(1.0 / 60);
  EXPECT_NEAR(m.targets()[0].x(), 100, 1e-9);
  EXPECT_NEAR(m.targets()[0].y(), 0, 1e-9);
  // the knob's next move turns from the pose again (soft takeover off: at once)
  m.apply(cc(16, 64));
  m.update(1.0 / 60);
  EXPECT_NEAR((m.targets()[0] - Vec2(0, 0)).norm(), 100, 1e-6);
}

// A pose eases every handle it names there over the binding's transition; a pose.KEY asks the
// loop for a recall; a pen dragging a handle returns it to rest over `return` seconds.
TEST(Poses, APoseEasesThereInItsTransitionAndAPenReturnsToRest) {
  Mapping m;
  m.set_handles({"a", "b"}, {Vec2(0, 0), Vec2(100, 0)});
  Pose p;
  p.name = "up";
  p.positions = {Vec2(0, -60), Vec2(NAN, NAN)};
  m.add_pose(p);
  Binding b = bind(ControlSpec::Note, 36, TargetKind::Pose);
  b.tf.transition = 0.5;
  m.add_binding(b);
  m.apply(note_event(36, true));
  const double dt = 1.0 / 60;
  int frames = 0;
  while (m.easing(0) && frames < 1000) {
    m.update(dt);
    ++frames;
    if (frames == 15) {
      EXPECT_NEAR(m.targets()[0].y(), -30, 1e-9);  // half way at half the time (in_out)
    }
    if (frames < 30) {
      EXPECT_GT(m.targets()[0].y(), -60);
    }
  }
  EXPECT_EQ(frames, 30);  // 0.5 s at 60 Hz
  EXPECT_DOUBLE_EQ(m.targets()[0].y(), -60);
  EXPECT_EQ(m.targets()[1], Vec2(100, 0));  // not named: left alone

  Binding r = bind(ControlSpec::Note, 37, TargetKind::Recall);
  r.index = 2;
  r.tf.transition = 0.8;
  r.tf.ease = Ease::Linear;
  m.add_binding(r);
  Recall rc;
  EXPECT_FALSE(m.take_recall(rc));
  m.apply(note_event(37, true));
  ASSERT_TRUE(m.take_recall(rc));
  EXPECT_EQ(rc.key, 2);
  EXPECT_EQ(rc.seconds, 0.8);
  EXPECT_EQ(rc.ease, Ease::Linear);
  EXPECT_FALSE(m.take_recall(rc));

  Binding pen = bind(ControlSpec::Pointer, 0, TargetKind::HandlePoint);
  pen.index = 1;
  pen.control.px = 1, pen.control.py = 2, pen.control.ptip = 3;
  pen.tf.area[0] = 0, pen.tf.area[1] = 0, pen.tf.area[2] = 200, pen.tf.area[3] = 200;
  pen.tf.ret = 0.25;
  pen.tf.ease = Ease::Linear;
  m.add_binding(pen);
  m.apply(hid_value(3, 1, 0, 1));
  m.apply(hid_value(1, 150, 0, 200));
  m.apply(hid_value(2, 50, 0, 200));
  m.update(dt);
  EXPECT_EQ(m.targets()[1], Vec2(150, 50));
  m.apply(hid_value(3, 0, 0, 1));  // lifted: back to rest in 0.25 s
  for (int k = 0; k < 6; ++k) m.update(dt);
  EXPECT_NEAR(m.targets()[1].x(), 150 - 50 * 0.4, 1e-9);  // linear: 0.1 s of 0.25
  for (int k = 0; k < 9; ++k) m.update(dt);
  EXPECT_EQ(m.targets()[1], Vec2(100, 0));
  EXPECT_FALSE(m.easing(1));
}

// Two pens, each grabbing a character of a cast (a grab binding's index): one holds at a time.
// Another pen hovering changes nothing; its tip going down takes over; lifting lets go.
TEST(Mapping, OnePenHoldsTheGrabAndAnotherPenDownTakesItOver) {
  Mapping m;
  m.set_handles({"a"}, {Vec2(0, 0)});
  for (int pen = 0; pen < 2; ++pen) {
    Binding g = bind(ControlSpec::Pointer, 0, TargetKind::Grab);
    g.control.device = uint16_t(pen);
    g.index = pen;  // the character it grabs
    g.control.px = 1, g.control.py = 2, g.control.ptip = 3;
    g.tf.area[0] = 0, g.tf.area[1] = 0, g.tf.area[2] = 100, g.tf.area[3] = 100;
    m.add_binding(g);
  }
  auto ev = [](uint16_t pen, uint32_t usage, int v, int hi) {
    Event e = hid_value(usage, v, 0, hi);
    e.source = pen;
    return e;
  };
  m.apply(ev(0, 1, 20, 100));
  m.apply(ev(0, 3, 1, 1));  // pen 0 down at (20, 50) (y: the middle until it moves)
  EXPECT_TRUE(m.grab_active());
  EXPECT_EQ(m.grab_who(), 0);
  m.apply(ev(1, 1, 80, 100));  // pen 1 hovers
  EXPECT_TRUE(m.grab_active());
  EXPECT_EQ(m.grab_who(), 0);
  EXPECT_EQ(m.grab_point(), Vec2(20, 50));
  m.apply(ev(1, 3, 1, 1));  // pen 1 down: it takes over
  EXPECT_EQ(m.grab_who(), 1);
  EXPECT_EQ(m.grab_point(), Vec2(80, 50));
  m.apply(ev(0, 1, 30, 100));  // pen 0, still down, moves: pen 1 keeps it
  EXPECT_EQ(m.grab_who(), 1);
  EXPECT_EQ(m.grab_point(), Vec2(80, 50));
  m.apply(ev(1, 3, 0, 1));  // pen 1 up: let go
  EXPECT_FALSE(m.grab_active());
  m.apply(ev(0, 1, 40, 100));  // pen 0, still down, holds again
  EXPECT_TRUE(m.grab_active());
  EXPECT_EQ(m.grab_who(), 0);
  EXPECT_EQ(m.grab_point(), Vec2(40, 50));
}

}  // namespace
}  // namespace mar
