// The show's idle behaviours ([[behavior]], motion/behavior.h): blinks on a trigger or a swap
// member, breathing and looking on a handle, a rotate group or a setting (a key's blend). Each
// pauses while a performer's binding writes the same target and comes back `resume` seconds
// after. The frame asks it, in order: step() (the key-pose stage), then what it adds to the
// settings the key poses read, to the handles' targets and to what shows (the motion stage).
// No allocation after prepare().
#pragma once

#include "app/show.h"
#include "motion/behavior.h"

#include <span>
#include <vector>

namespace mar {

class IdleStage {
 public:
  void prepare(const ShowConfig& show, const Mapping& m);
  bool empty() const { return items_.empty(); }
  bool has_blinks() const { return blinks_; }
  size_t size() const { return items_.size(); }
  /// One frame: each behaviour, paused while a binding on its target moved this frame.
  /// `beats`: the music time (motion/beat_clock.h), for behaviours with sync = "beat".
  void step(double dt, const Mapping& m, double beats = 0);
  /// What the behaviours add to setting `i` now.
  double setting_offset(int i) const;
  /// Offsets the handles' targets and turns the rotate groups' (the rig's handles).
  void apply_targets(std::span<Vec2> targets, const std::vector<RotationGroup>& groups, std::span<const Vec2> pivots) const;
  /// What shows: the mapping's swap members and triggers with the blinks over them. Returns
  /// whether it differs from the last call's.
  bool shown(std::span<const int> members, std::span<const char> triggers);
  std::span<const int> members() const { return members_; }
  std::span<const char> triggers() const { return triggers_; }
  const Behavior& behavior(size_t i) const { return items_[i].b; }

 private:
  struct Item {
    Behavior b;
    TargetKind target;
    int index, member;
    std::vector<size_t> writers;  ///< bindings on the same target
    uint64_t hits = 0;            ///< their uses, last frame
  };
  std::vector<Item> items_;
  std::vector<int> members_, last_members_;
  std::vector<char> triggers_, last_triggers_;
  bool first_ = true, blinks_ = false;
};

}  // namespace mar
