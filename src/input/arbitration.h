// Priority arbitration: who drives a target that several sources (bindings of different
// performers' controls) set.
//
// Each source keeps its own value: what it last set. The holder's value is the target's. A
// source that sets its value takes the target when it has at least the holder's priority, or
// when the holder has let go (not moved for its `hold` seconds); otherwise it waits, its
// value kept. When the holder lets go, the highest-priority source that moved within its own
// hold takes over, else the lowest-priority source that has a value (the base a performer
// overrode). Every change of holder after the first is a hand-over: the target eases
// (in-out) from where it is to the new holder's value, which it follows as it moves, over
// the new holder's `handover` seconds. No jump, whoever takes the target.
//
// Time is the caller's clock in seconds (the show's: the virtual clock when headless, so
// a recording replays the same hand-overs). Sized at load; write() and update() allocate
// nothing.
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

namespace mar {

struct SourcePriority {
  int priority = 0;
  double hold = 1.0;      ///< seconds without a move before it lets go
  double handover = 0.5;  ///< seconds to ease the target to this source when it takes it
};

class Arbiter {
 public:
  /// The target's sources, in a fixed order (a source is its index).
  void set_sources(std::vector<SourcePriority> sources);
  std::size_t sources() const { return spec_.size(); }

  /// Source `s` set its value `v` at time `now`.
  void write(int s, double v, double now);
  /// Source `s`'s own value (NaN before it set one).
  double own(int s) const { return own_[std::size_t(s)]; }
  /// Advances the clock to `now` (by `dt`): a holder that let go hands over. Returns the
  /// target's value (NaN while no source has set one).
  double update(double now, double dt);
  /// The target's value as of the last write or update (NaN while no source has set one).
  double value() const { return value_; }
  /// The holder (-1: none yet), and whether a hand-over is easing toward it.
  int holder() const { return holder_; }
  bool handing_over() const { return easing_; }
  /// Whether source `s` moved within its hold at `now`.
  bool active(int s, double now) const;
  /// Sets every source's value back to none (a reload that drops the state).
  void reset();

 private:
  void take(int s);
  double follow() const;

  std::vector<SourcePriority> spec_;
  std::vector<double> own_, moved_;
  int holder_ = -1;
  double value_ = std::numeric_limits<double>::quiet_NaN();
  bool easing_ = false;
  double from_ = 0, t_ = 0, seconds_ = 0;
};

}  // namespace mar
