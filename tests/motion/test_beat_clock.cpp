// The music time (motion/beat_clock.h) and the behaviours that follow it (sync = "beat"): it
// locks to a clock's beats within about half a second without a jump, runs on at the last tempo
// when the clock stops, and a synced breath, blink and look count beats.
#include "motion/beat_clock.h"
#include "motion/behavior.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mar {
namespace {

// A clock at `bpm` whose song starts at `t0` s; ticks (24 a beat) are fed up to each frame.
struct Music {
  double bpm, t0;
  double beats_at(double t) const { return (t - t0) * bpm / 60; }
};

TEST(BeatClock, LocksToTheClocksBeatsSmoothlyAndRunsOnWhenItStops) {
  const Music m{100, 0.37};
  BeatClock c;
  const double dt = 1.0 / 120, tick = 60.0 / (m.bpm * 24);
  double next_tick = m.t0, last = 0, worst_step = 0;
  for (int f = 0; f < 120 * 6; ++f) {  // 6 s: the clock plays from 0.37 s to 4 s
    const double t = f * dt;
    while (next_tick <= t && next_tick < 4.0) {
      const double b = m.beats_at(next_tick);
      c.tick(b / 4 - std::floor(b / 4), m.bpm, int64_t(std::llround(next_tick * 1e9)));
      next_tick += tick;
    }
    c.step(int64_t(std::llround(t * 1e9)), f ? dt : 0);
    if (f) worst_step = std::max(worst_step, std::abs((c.beats() - last) - dt * c.bpm() / 60));
    last = c.beats();
    if (t > 1.5 && t < 4.0) {  // locked: the music time is the clock's, to the bar
      ASSERT_TRUE(c.locked()) << t;
      const double err = std::remainder(c.beats() - m.beats_at(t), 4.0);
      EXPECT_LT(std::abs(err), 0.005) << "at " << t << " s";  // (2.5 ms at 100 BPM)
    }
  }
  EXPECT_LT(worst_step, 0.1) << "pulled in, never jumped";
  EXPECT_FALSE(c.locked());  // no tick for 2 s
  // Stopped at 4 s: on at 100 BPM since.
  EXPECT_NEAR(std::remainder(c.beats() - m.beats_at(6.0 - dt), 4.0), 0, 0.01);
}

TEST(BeatClock, WithoutAClockItRunsAt120Bpm) {
  BeatClock c;
  for (int f = 1; f <= 60; ++f) c.step(int64_t(f * 1e9 / 60), 1.0 / 60);
  EXPECT_NEAR(c.beats(), 2.0, 1e-9);
  EXPECT_FALSE(c.locked());
}

TEST(Behavior, OnTheBeatABreathCountsBeatsAndABlinkStartsOnABeat) {
  BehaviorSpec s;
  s.kind = BehaviorSpec::Breathe;
  s.sync_beat = true;
  s.period = 2;  // beats
  s.amount = 1;
  Behavior breathe(s);
  breathe.step(0.01, false, 1.0);  // half a breath: the top
  EXPECT_NEAR(breathe.value(), 1.0, 1e-12);
  breathe.step(0.01, false, 2.0);
  EXPECT_NEAR(breathe.value(), 0.0, 1e-12);
  breathe.step(5.0, false, 2.5);  // whatever the seconds, the beats count
  EXPECT_NEAR(breathe.value(), 0.5, 1e-12);

  BehaviorSpec b;
  b.kind = BehaviorSpec::Blink;
  b.sync_beat = true;
  b.mean = 3;  // beats
  b.jitter = 0.5;
  b.hold = 0.1;
  Behavior blink(b);
  const double dt = 1.0 / 120, bpm = 90;
  bool was = false;
  int starts = 0;
  double last_start = -1;
  int start_f = 0;
  for (int f = 1; f <= 120 * 60; ++f) {
    const double beats = f * dt * bpm / 60;
    blink.step(dt, false, beats);
    if (blink.on() && !was) {
      ++starts;
      EXPECT_LT(beats - std::floor(beats), dt * bpm / 60 + 1e-9) << "a blink starts in the frame a beat falls in";
      if (last_start >= 0) {
        EXPECT_GE(beats - last_start, 1.0 - 1e-9);
        EXPECT_LE(beats - last_start, 3 * 1.5 + 1 + 1e-9);
      }
      last_start = beats;
      start_f = f;
    }
    if (was && !blink.on()) {
      EXPECT_NEAR((f - start_f) * dt, 0.1, dt + 1e-9);  // (its hold stays in seconds)
    }
    was = blink.on();
  }
  EXPECT_GT(starts, 20);  // 90 beats in a minute, a blink every 1.5..4.5 beats
}

}  // namespace
}  // namespace mar
