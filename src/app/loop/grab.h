// Grab-and-drag with a pen: while the pointer's tip is down, the character point nearest the
// pen follows it. Near an existing handle (within 5% of the character's diagonal) the pen
// takes that handle over, keeping its offset (two handles side by side would pull against
// each other); elsewhere the nearest shape point becomes a temporary handle, added to the
// factorised system by a rank-2 update (no re-factorisation, no allocation).
#pragma once

#include "app/puppet.h"
#include "app/stats.h"

#include <span>
#include <vector>

namespace mar {

class Grab {
 public:
  /// The tip went down at `point` (character units) or came up.
  void set(bool down, const Vec2& point, Puppet& p);
  /// After the solver re-factorised (new parameters): a temporary handle is added again.
  void restore(const Vec2& point, Puppet& p);
  /// Writes the grab's target into `handles` (the rig's handles' targets: a handle taken over)
  /// or `temporary` (the temporary handle's) and returns how many targets the solve uses.
  size_t apply(const Vec2& point, std::span<Vec2> handles, Vec2& temporary) const;
  bool active() const { return active_; }
  /// The handle taken over, or -1 (a temporary handle, or no grab).
  int handle() const { return active_ ? handle_ : -1; }
  long count() const { return count_; }
  const Histogram& cost_us() const { return cost_us_; }

 private:
  bool active_ = false;
  int handle_ = -1;
  Vec2 offset_ = Vec2::Zero();
  long count_ = 0;
  Histogram cost_us_;
};

}  // namespace mar
