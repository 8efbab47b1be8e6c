// Idle behaviours (issue: a character that is alive): what a character does when nobody moves
// it — it blinks, breathes and looks about. Pure state: a behaviour is stepped each frame and
// gives an on/off (a blink), an offset or a value (breathing, looking); the show decides what
// they drive (app/loop/idle.h).
//   blink    on for `hold` seconds at random intervals: mean · (1 ± jitter), from `seed`
//   breathe  (1 − cos(2π t / period)) / 2 of its depth: an offset, or a key's weight
//   look     slow smooth noise (`speed` Hz) within ± its range: an offset, or degrees
// While a performer's control writes the behaviour's target it pauses (its weight falls to 0
// at once); `resume` seconds after the last such write it fades back in over `fade` seconds.
// Everything is a function of the frames' steps and the seed: the same show gives the same
// blinks on every run. Nothing allocates.
#pragma once

#include "geom/types.h"

#include <cstdint>

namespace mar {

struct BehaviorSpec {
  enum Kind { Blink, Breathe, Look } kind = Blink;
  double mean = 4, jitter = 0.5, hold = 0.15;  ///< blink: seconds between, ± fraction, seconds shut
  double period = 4;                            ///< breathe: seconds a breath
  Vec2 depth{0, -3};                            ///< breathe: the offset at the top of a breath
  Vec2 range{8, 4};                             ///< look: ± offset
  double amount = 1;                            ///< a scalar target's: breathe's top, look's ± range
  double speed = 0.15;                          ///< look: Hz of the noise
  uint64_t seed = 1;
  double resume = 2, fade = 0.5;                ///< after a performer's last write
  /// On the music (sync = "beat"): period and mean count beats, speed is per beat, a blink
  /// starts on a beat (its hold stays in seconds). The music time comes to step().
  bool sync_beat = false;
};

class Behavior {
 public:
  explicit Behavior(const BehaviorSpec& s);
  /// One frame of `dt` seconds; `touched`: a performer's control wrote the target this frame;
  /// `beats`: the music time now (motion/beat_clock.h), used when the spec syncs to the beat.
  void step(double dt, bool touched, double beats = 0);
  /// Blink: shut now.
  bool on() const { return on_; }
  /// Breathe, look: the offset now (times weight()).
  Vec2 offset() const;
  /// Breathe, look: the scalar now (times weight()): a key's weight, degrees, one axis.
  double value() const;
  /// 1 while it runs, 0 while a performer holds its target, fading between.
  double weight() const { return weight_; }
  long blinks() const { return blinks_; }
  const BehaviorSpec& spec() const { return s_; }

 private:
  double next_interval();
  BehaviorSpec s_;
  uint64_t rng_;
  double t_ = 0;            ///< seconds run
  double tau_ = 0;          ///< what its cycles count: t_, or the music time in beats (sync)
  double until_ = 0;        ///< blink: the next one starts (or, on, ends) at this t_ (sync: starts at this beat)
  double shut_until_ = 0;   ///< blink on the beat: it opens at this t_
  bool on_ = false;
  long blinks_ = 0;
  double weight_ = 1, since_touch_ = 1e9;
};

}  // namespace mar
