#include "motion/beat_clock.h"

#include <cmath>

namespace mar {

void BeatClock::tick(double bar_phase, double bpm, int64_t t_ns) {
  if (!std::isfinite(bar_phase)) return;
  bar_phase = bar_phase - std::floor(bar_phase);
  if (heard_ && bar_phase < bar_phase_ - 0.5) bars_ += 1;  // the bar came round
  bar_phase_ = bar_phase;
  if (bpm > 0 && std::isfinite(bpm)) bpm_ = bpm;
  tick_ns_ = t_ns;
  heard_ = true;
}

double BeatClock::clock_beats(int64_t t_ns) const {
  return kBeatsPerBar * (bars_ + bar_phase_) + double(t_ns - tick_ns_) * 1e-9 * bpm_ / 60;
}

void BeatClock::step(int64_t t_ns, double dt) {
  if (!(dt >= 0) || !std::isfinite(dt)) dt = 0;
  beats_ += dt * bpm_ / 60;
  locked_ = heard_ && t_ns - tick_ns_ < 1'000'000'000 && t_ns >= tick_ns_;
  if (!locked_) return;
  // The error to the clock, wrapped to the nearest bar (-2..2 beats): pulled in with a time
  // constant of 0.15 s, so a new clock is followed within about half a second, smoothly.
  const double bar = kBeatsPerBar;
  const double err = std::remainder(clock_beats(t_ns) - beats_, bar);
  beats_ += err * (1 - std::exp(-dt / 0.15));
}

}  // namespace mar
