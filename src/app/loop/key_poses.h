// Key poses in a show (seed 000 §5, docs/key-poses.md): the frame's "poses" stage.
//
// The morph.A.B and blend.KEY settings give weights over the rig's keys (a morph from A to B
// at t puts 1 − t on A and t on B; blends add); a pose recall (pose.KEY) eases an offset over
// those weights from where it is to what makes the sum that key (or rest), and knobs turned
// afterwards add their change on top. The weights' interpolated frame is the base pose; every
// handle's target moves by where the base pose has it (the performer's own offsets ride on
// top). Blending happens only when the weights change. A sculpted key (the studio's brush or
// curve: RigKey::shapes) also has detail its handles alone do not make (app/keys.h): the
// weights' share of it is laid on the solve's frame (detail_onto), each part's carried by the
// part's turn from the base pose to the solve.
//
// Made at load (its settings, its interpolator); step() and offset() allocate nothing.
#pragma once

#include "app/puppet.h"
#include "input/mapping.h"
#include "interp/interpolation.h"

#include <memory>
#include <span>
#include <string>
#include <vector>

namespace mar {

struct ShowConfig;

class KeyPoseStage {
 public:
  /// A setting that drives keys: morph (from, to: keys, -1 rest) or blend (from = -2, to = key).
  struct KeySetting {
    int setting, from, to;
  };
  /// Adds a morph.A.B setting for every ordered pair of keys and rest, then a blend.KEY for
  /// each key, to the mapping (their ranges 0..1), in the order the show names them (ShowRig).
  void add_settings(Mapping& m, int keys);
  /// Keeps only the settings a binding or an idle behaviour drives (an unbound morph.A.B would
  /// hold key A at t = 0). Returns whether the poses stage is wanted: a setting is driven, or
  /// a binding recalls a pose of the cast's character `who` (0: a show's single rig).
  bool keep_driven(const ShowConfig& sh, int who = 0);
  /// Prepares the interpolation over the rig's keys (solved: app/keys.h). Empty, or the error.
  /// `details`: per key, its sculpted detail (empty: none; app/keys.h solve_keys).
  std::string prepare(const Puppet& p, const std::vector<Points>& keys, const std::vector<Points>* details = nullptr);
  bool empty() const { return !interp_; }
  const std::vector<KeySetting>& settings() const { return settings_; }

  /// One frame of `dt` seconds: `values` holds each of settings()' value this frame (the
  /// mapping's, crossfaded with the attract's, plus an idle behaviour's); `recall` a pose
  /// recall a control asked for this frame, or nullptr. Returns true when the recall jumps
  /// (0 seconds: secondary motion starts again at rest).
  bool step(double dt, std::span<const double> values, const Recall* recall);
  /// Adds the base pose's offset from rest to each handle's target (the first #handles).
  void offset(std::span<Vec2> targets) const;
  /// This frame's weight of each key.
  std::span<const double> weights() const { return weights_; }
  /// Whether a key is sculpted (has detail); whether this frame's weights hold some.
  bool has_detail() const { return !detail_.empty(); }
  bool detailed() const { return detailed_; }
  /// The solve's frame vertices `v` with this frame's sculpted detail on them, into `out` (#q).
  /// No allocation.
  void detail_onto(std::span<const Vec2> v, std::span<Vec2> out) const;

 private:
  std::vector<KeySetting> settings_;
  std::unique_ptr<KeyInterpolator> interp_;
  const Puppet* puppet_ = nullptr;
  std::vector<double> weights_, last_weights_;
  Points base_frame_;
  std::vector<Vec2> base_offset_;  ///< per handle: base pose minus rest
  std::vector<double> recall_w_, recall_from_, recall_to_;
  std::vector<Points> details_;             ///< per key (empty: not sculpted)
  Points detail_;                           ///< this frame's weights' detail (#q)
  bool detailed_ = false;
  std::vector<std::vector<int>> part_vertices_;  ///< per shape: its frame vertices
  mutable std::vector<Vec2> from_, to_;     ///< (room for the largest part)
  double recall_t_ = 0, recall_seconds_ = 0;
  Ease recall_ease_ = Ease::InOut;
  bool recall_on_ = false;
};

}  // namespace mar
