// Music time for motion that follows a MIDI clock (`sync = "beat"` on behaviours and on the
// show's physics; docs/algorithms.md §8). The clock's ticks report where the bar is and the tempo
// (input/midi_clock.h fits them); each frame the music time advances at the tempo and is pulled
// toward the clock's position, the error wrapped to the nearest bar, so that it locks to the
// beat within about half a second and never jumps. Without a clock (none yet, stopped, or
// unplugged: no tick for a second) it runs on at the last tempo, 120 BPM before any. The same
// ticks at the same show times give the same music time: deterministic, allocation-free.
#pragma once

#include <cstdint>

namespace mar {

class BeatClock {
 public:
  static constexpr int kBeatsPerBar = 4;
  /// A tick's report at show time `t_ns`: the phase within the bar (0..1) and, when known, the
  /// tempo (BPM; <= 0: unchanged).
  void tick(double bar_phase, double bpm, int64_t t_ns);
  /// The frame at show time `t_ns`, `dt` seconds after the last.
  void step(int64_t t_ns, double dt);
  /// Beats now (music time; whole beats fall on the clock's beats once locked).
  double beats() const { return beats_; }
  double bpm() const { return bpm_; }
  /// A tick came within the last second.
  bool locked() const { return locked_; }

 private:
  double clock_beats(int64_t t_ns) const;
  double beats_ = 0, bpm_ = 120;
  double bar_phase_ = -1, bars_ = 0;  ///< the clock's song: bars counted by the phase's wraps
  int64_t tick_ns_ = 0;
  bool heard_ = false, locked_ = false;
};

}  // namespace mar
