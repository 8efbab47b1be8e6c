// The rigid motion the performer asks of a set of a character's handles this frame: their
// targets' best fit from their rest (one handle: its move). What the pen's tools carry what they
// hold by (app/loop/brush.h, curve.h) — never where the solve put a part, which they pull
// themselves, and never a secondary-motion chain's end, which follows the pose.
#pragma once

#include "app/puppet.h"
#include "geom/polygon.h"

#include <span>
#include <vector>

namespace mar {

class HandleMotion {
 public:
  /// The handles' rest and which of them move parts (all but chains' ends). Allocates.
  void prepare(const Puppet& p) {
    rest_ = p.rest_targets();
    targets_ = rest_;
    from_.assign(rest_.size(), Vec2::Zero());
    to_.assign(rest_.size(), Vec2::Zero());
    free_.clear();
    for (size_t h = 0; h < rest_.size() && h < p.rig.handles.size(); ++h)
      if (!p.rig.handles[h].physics) free_.push_back(int(h));
    // Each part's handles: a handle is bound to a line of the frame, its first vertex's part.
    part_.assign(p.character.shapes.size(), {});
    if (const FeatureFrameMethod* ff = p.feature_frame()) {
      const std::span<const ShapeParam> bind = ff->bindings();
      for (int h : free_) {
        if (size_t(h) >= bind.size()) continue;
        const int shape = ff->frame().origin[size_t(bind[size_t(h)].a)].shape;
        if (shape >= 0 && size_t(shape) < part_.size()) part_[size_t(shape)].push_back(h);
      }
    }
  }
  /// This frame's targets (the character's handles, rig order). No allocation.
  void set_targets(std::span<const Vec2> targets) {
    for (size_t h = 0; h < targets_.size() && h < targets.size(); ++h) targets_[h] = targets[h];
  }
  /// The motion `handles` ask for (empty: every handle but chains' ends). No allocation.
  RigidMotion of(std::span<const int> handles) const {
    if (handles.empty()) handles = free_;
    if (handles.size() == 1) {
      RigidMotion m;
      m.from_c = rest_[size_t(handles[0])];
      m.to_c = targets_[size_t(handles[0])];
      return m;
    }
    size_t n = 0;
    for (int h : handles) {
      from_[n] = rest_[size_t(h)];
      to_[n++] = targets_[size_t(h)];
    }
    return rigid_fit(std::span<const Vec2>(from_.data(), n), std::span<const Vec2>(to_.data(), n));
  }
  /// The motion part `shape`'s handles ask for (none on it: every handle's). No allocation.
  RigidMotion of_part(int shape) const {
    return shape >= 0 && size_t(shape) < part_.size() ? of(part_[size_t(shape)]) : of({});
  }
  const Vec2& rest(size_t h) const { return rest_[h]; }
  /// The handles that move parts (all but chains' ends).
  std::span<const int> free_handles() const { return free_; }

 private:
  std::vector<Vec2> rest_, targets_;
  std::vector<int> free_;
  std::vector<std::vector<int>> part_;   ///< per shape: the handles bound to it (chains' ends not)
  mutable std::vector<Vec2> from_, to_;  ///< (room for every handle)
};

}  // namespace mar
