// MIDI clock (input/midi_clock.h): tempo and beat phase from ticks with 1 ms of jitter —
// measured against the clock's own schedule: the tempo within 0.1 BPM and the beat within 2 ms
// (the goals) at 60, 120 and 174 BPM; a tempo change relocks within a beat; start, stop
// and continue move the song position as the MIDI spec says; and through the decoder, the
// simulated nanoKONTROL2's clock becomes beat and bar phase events.
#include "firmware_sim/midi_controller.h"
#include "input/decoder.h"
#include "input/midi_clock.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace mar {
namespace {

// Ticks at `bpm` from `t0` (ns), each off its time by up to ±jitter (uniform, seeded).
std::vector<int64_t> ticks(double bpm, double seconds, double jitter_s, uint32_t seed, int64_t t0 = 1000000000) {
  std::vector<int64_t> t;
  const double period = 60.0 / (bpm * 24);
  uint32_t x = seed;
  for (long k = 0; double(k) * period < seconds; ++k) {
    x = x * 1664525u + 1013904223u;
    const double j = jitter_s * (2.0 * double(x >> 8) / double(1u << 24) - 1.0);
    t.push_back(t0 + std::llround((double(k) * period + j) * 1e9));
  }
  return t;
}

TEST(MidiClock, TempoWithinATenthOfABpmAndTheBeatWithinTwoMillisecondsWithOneMillisecondOfJitter) {
  for (const double bpm : {60.0, 120.0, 174.0}) {
    MidiClock c;
    c.start();
    const auto t = ticks(bpm, 20, 0.001, 7);
    const double period_ns = 60e9 / (bpm * 24);
    double worst_bpm = 0;
    std::vector<double> phase_err;
    for (size_t k = 0; k < t.size(); ++k) {
      c.tick(t[k]);
      if (k < 2 * 24) continue;  // two beats to settle
      worst_bpm = std::max(worst_bpm, std::abs(c.bpm() - bpm));
      // The beat the clock says is nearest now, against when it truly was.
      const double beat = std::round(c.beats_at(t[k]));
      const double said = c.tick_time_ns(beat * 24), truth = 1e9 + beat * 24 * period_ns;
      phase_err.push_back(std::abs(said - truth) * 1e-6);
    }
    std::sort(phase_err.begin(), phase_err.end());
    const double p99 = phase_err[size_t(0.99 * double(phase_err.size()))], max = phase_err.back();
    std::printf("%.0f BPM, 1 ms jitter: tempo off by at most %.4f BPM; beat off by p99 %.3f ms, max %.3f ms\n", bpm, worst_bpm, p99, max);
    EXPECT_LE(worst_bpm, 0.1) << bpm;
    EXPECT_LE(max, 2.0) << bpm;
  }
}

TEST(MidiClock, ATempoChangeRelocksWithinABeat) {
  MidiClock c;
  c.start();
  auto a = ticks(120, 4, 0.001, 3);
  const int64_t end = a.back() + std::llround(60e9 / (120 * 24));
  auto b = ticks(90, 4, 0.001, 5, end);
  for (int64_t t : a) c.tick(t);
  EXPECT_NEAR(c.bpm(), 120, 0.1);
  for (size_t k = 0; k < b.size(); ++k) {
    c.tick(b[k]);
    if (k == 24) {
      EXPECT_NEAR(c.bpm(), 90, 1.0) << "a beat after the change";
    }
  }
  EXPECT_NEAR(c.bpm(), 90, 0.1);
}

// A recording can carry any 64-bit tick times (fuzz_recording found ticks from near INT64_MIN
// to +0.36 s, whose difference overflowed): the clock stays finite and relocks on the next
// steady ticks.
TEST(MidiClock, TicksFromTheEndsOfTimeLeaveItFiniteAndItRelocks) {
  MidiClock c;
  c.start();
  for (const int64_t t : {INT64_MIN, INT64_MIN + 1, int64_t{358000000}, INT64_MAX, INT64_MIN / 2, int64_t{0},
                          INT64_MAX, INT64_MAX - 1, INT64_MIN})
    c.tick(t);
  EXPECT_TRUE(std::isfinite(c.bpm()));
  EXPECT_TRUE(std::isfinite(c.beats_at(0)));
  for (const int64_t t : ticks(120, 4, 0, 1)) c.tick(t);
  EXPECT_NEAR(c.bpm(), 120.0, 0.01);
}

TEST(MidiClock, StartStopAndContinueMoveTheSongPositionAsTheSpecSays) {
  MidiClock c;
  const auto t = ticks(120, 10, 0, 1);  // ticks every 20.833 ms, no jitter
  size_t k = 0;
  c.start();
  for (; k < 48; ++k) c.tick(t[k]);  // two beats: ticks 0..47
  EXPECT_NEAR(c.beats_at(t[47]), 47.0 / 24, 1e-6);
  EXPECT_NEAR(c.beat_phase(t[47]), 23.0 / 24, 1e-6);
  c.stop();
  for (; k < 96; ++k) c.tick(t[k]);  // ticks go on while stopped: the tempo stays, the song holds
  EXPECT_FALSE(c.running());
  EXPECT_NEAR(c.bpm(), 120, 1e-6);
  EXPECT_NEAR(c.beats_at(t[95]), 47.0 / 24, 1e-6) << "held where it stopped";
  c.resume();
  c.tick(t[96]);  // the next song tick: 48
  EXPECT_NEAR(c.beats_at(t[96]), 2.0, 1e-6);
  c.start();  // from the top: the next tick is beat 0
  c.tick(t[97]);
  EXPECT_NEAR(c.beats_at(t[97]), 0.0, 1e-6);
  EXPECT_NEAR(c.bar_phase(t[97] + std::llround(60e9 / 120 * 2)), 0.5, 1e-6) << "two beats on: half a bar";
}

TEST(MidiClock, TheSimulatedControllersClockBecomesBeatAndBarPhases) {
  MidiControllerSim sim;
  ASSERT_TRUE(sim.load_script("0.5 clock 120 jitter 0.001 for 4\n").ok());
  auto dec = make_decoder(sim.decoder_config(), 0, nullptr);
  ASSERT_NE(dec, nullptr);
  std::vector<Event> events;
  for (const auto& r : sim.timeline()) dec->feed(r, [&](const Event& e) { events.push_back(e); });
  std::vector<const Event*> beats;
  for (const Event& e : events)
    if (e.kind == ControlKind::ClockPhase && e.number == kClockBeat) beats.push_back(&e);
  ASSERT_GE(beats.size(), size_t(4 * 48 - 10)) << "a beat phase at every tick once locked";
  // On the beat (every 24th tick from the start) the phase is 0 (or just under 1), within 2 ms.
  int on_beat = 0;
  for (const Event* e : beats) {
    const double phase = double(e->value) / kClockPhaseMax;
    const double since = double(e->t_ns) * 1e-9 - 0.5, beat = std::round(since * 2);
    if (std::abs(since - beat / 2) < 0.005) {  // a tick within 5 ms of a true beat
      EXPECT_LT(std::min(phase, 1 - phase), 0.002 / 0.5) << "at " << since << " s";
      ++on_beat;
    }
  }
  EXPECT_GE(on_beat, 6);
}

}  // namespace
}  // namespace mar
