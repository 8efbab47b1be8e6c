// The show's music time: MIDI clock events (input/midi_decoder.cpp sends, per tick, the tempo,
// the beat's and the bar's phase) into the beat clock that synced behaviours and physics follow
// (motion/beat_clock.h).
#pragma once

#include "input/event.h"
#include "motion/beat_clock.h"

namespace mar {

class MusicTime {
 public:
  void event(const Event& e) {
    if (e.kind != ControlKind::ClockPhase) return;
    if (e.number == kClockTempo) bpm_ = double(e.value) * 1e-3;
    else if (e.number == kClockBar) clock_.tick(normalized(e), bpm_, e.t_ns);
  }
  void step(int64_t t_ns, double dt) { clock_.step(t_ns, dt); }
  double beats() const { return clock_.beats(); }
  const BeatClock& clock() const { return clock_; }

 private:
  BeatClock clock_;
  double bpm_ = 0;
};

}  // namespace mar
