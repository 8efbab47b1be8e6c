// One character of a show's cast: its puppet and solver, its key poses, its secondary motion and
// the pen's grab on it, and its place on the canvas. The stage (LiveShow) reads the devices and
// runs one Mapping for the whole cast: an actor's handles, settings, swap sets and triggers are a
// range of the mapping's (Actor::Ranges), so arbitration, the HUD, the lights, idle behaviours
// and the attract loop see one show. Each frame an actor takes its slice of the stage's targets
// through its stages — poses, motion, solve, then its shapes and draw list — and touches nothing
// of another actor's: actors can solve on threads of their own.
//
// A show with `[show] rig` alone is a cast of one whose ranges start at 0: it computes exactly
// what the show computed before there was a cast.
#pragma once

#include "app/loop/brush.h"
#include "app/loop/contour.h"
#include "app/loop/curve.h"
#include "app/loop/grab.h"
#include "app/loop/key_poses.h"
#include "app/loop/physics.h"
#include "app/puppet.h"
#include "app/show.h"
#include "render/tessellate.h"

#include <memory>
#include <span>
#include <string>
#include <vector>

namespace mar {

class Attract;
class IdleStage;

class Actor {
 public:
  /// Where the actor's names live in the stage's mapping.
  struct Ranges {
    size_t handle0 = 0, handles = 0;   ///< its handles
    int solver0 = 0;                   ///< its solver's parameters (then its key settings)
    int physics0 = 0;                  ///< its [[physics]] chains' settings
    size_t swap0 = 0, swaps = 0;       ///< its swap sets
    size_t trigger0 = 0, triggers = 0; ///< its triggers
    int who = 0;                       ///< its index in the cast (a recall's or a grab's character)
  };

  /// Adds the actor's settings to `m` (its solver's parameters, its key poses', its chains') and
  /// prepares its key poses and motion. `sh`'s bindings are resolved; `swap0` and `trigger0`:
  /// where its swap sets and triggers start among the cast's. Empty, or the error.
  /// `p` may be a running show's (a reload that keeps it, its files unchanged): then only what
  /// posing never writes is read of it (Puppet::loaded_parameters, solved_keys, the drawing and
  /// the rig), and take_puppet_from() takes it over at the swap.
  std::string prepare(std::shared_ptr<Puppet> p, const ShowConfig& sh, Mapping& m, size_t handle0, size_t swap0,
                      size_t trigger0, int who);

  const std::string& name() const { return name_; }
  void set_name(std::string n) { name_ = std::move(n); }
  const Ranges& ranges() const { return r_; }
  Puppet& puppet() { return *puppet_; }
  const Puppet& puppet() const { return *puppet_; }
  std::shared_ptr<Puppet> shared_puppet() const { return puppet_; }

  /// New solver parameters from the mapping: re-factorises when they changed (allocates).
  /// Returns whether it did.
  bool apply_settings(const Mapping& m);
  /// The pen went down or came up on this actor at `point` (character units).
  void set_grab(bool down, const Vec2& point) { grab_.set(down, point, *puppet_); }
  /// Writes the grab's target into the actor's slice of the stage's targets (a handle taken
  /// over), or into its own slot (a temporary handle).
  void apply_grab(const Vec2& point, std::span<Vec2> targets);
  const Grab& grab() const { return grab_; }

  /// This frame's pen for the brush or the curve (`brush`, `curve`: its [[brush]] or [[curve]]
  /// when the pen is this actor's, else nullptr) and the frame's seconds; they step in
  /// solve(). No allocation.
  void set_pen(const Mapping::Pen& pen, const ShowBrush* brush, const ShowCurve* curve, double dt) {
    pen_ = pen;
    pen_spec_ = brush;
    curve_spec_ = curve;
    pen_dt_ = dt;
  }
  bool has_brush() const { return brush_.prepared(); }
  bool has_curve() const { return curve_.prepared() || contour_.prepared(); }
  const BrushStage& brush() const { return brush_; }
  const CurveStage& curve() const { return curve_; }
  const ContourStage& contour() const { return contour_; }

  // The stages of a frame, on the actor's slice of the stage's targets (mapping order).
  /// Key poses: the weights from this frame's settings (`setting_value`: the mapping's,
  /// crossfaded with the attract's, with idle offsets), a recall if one was asked for this
  /// actor; then the base pose's offsets on the targets.
  template <class SettingValue>
  void poses(double dt, SettingValue&& setting_value, const Recall* recall, std::span<Vec2> targets) {
    if (keys_.empty()) return;
    const auto& ks = keys_.settings();
    for (size_t i = 0; i < ks.size(); ++i) key_values_[i] = setting_value(ks[i].setting);
    if (!recall && tool_recall_on_) recall = &tool_recall_;  // (a pen tool let go into a key)
    tool_recall_on_ = false;
    if (keys_.step(dt, key_values_, recall)) physics_.reset();  // a jump: the chains start again at rest
    keys_.offset(targets);
  }
  /// Secondary motion: the chains' settings (`setting_value` as above), then a fixed-step run.
  template <class SettingValue>
  void motion(double dt, double beats, SettingValue&& setting_value, std::span<Vec2> targets) {
    if (physics_.empty()) return;
    for (size_t k = 0, n = physics_.setting_count(); k < n; ++k) physics_.set(k, setting_value(r_.physics0 + int(k)));
    physics_.set_beats(beats);
    physics_.step(dt, *puppet_, targets);
  }
  /// The solve, from its slice of the stage's targets (and the grab's slot).
  void solve(std::span<const Vec2> targets, int iterations);
  /// The shapes from the solve, blended from a reload's last drawing while one is under way;
  /// returns the worst part's distortion, % of the height (which part: worst_shape()).
  double reconstruct();
  int worst_shape() const { return worst_shape_; }
  /// Its shapes as now posed, on its view as now drawn, at its opacity.
  void draw(DrawList& list) const;

  bool has_keys() const { return !keys_.empty(); }
  std::span<const double> key_weights() const { return keys_.weights(); }
  const PhysicsStage& physics() const { return physics_; }

  /// Where it stands: character units -> canvas px; canvas px (at the show's size) per unit.
  Affine2 view;
  double px_per_unit = 1;
  bool shown = true;
  int z = 0;
  /// Entering and leaving (its NAME.on-stage trigger): a fade, or a slide from `offstage` (canvas
  /// px from where it stands), over `entrance_s` seconds; 0 s: a cut.
  bool fade = true;
  Vec2 offstage{0, 0};
  double entrance_s = 0.6;
  /// Moves its presence toward on stage (`on`) or off it by a frame of `dt` seconds.
  void stage_step(bool on, double dt);
  /// 0: off stage (not drawn) .. 1: on stage; its opacity and view as now drawn.
  double presence() const { return presence_; }
  float opacity() const;
  Affine2 drawn_view() const;
  /// How deep its drawing's layers nest (with the layer of its fade, when it fades), and how
  /// many it may have at once: what the canvas makes room for at load.
  size_t layer_depth() const;
  size_t layer_count() const { return puppet_->character.composites.size() + (fade ? 1 : 0); }
  /// Its rest box (the HUD keeps off it) and where its drawing covers that box.
  Bounds rest_bounds;
  static constexpr int kCoverCells = 24;
  std::vector<uint8_t> rest_cover;

  /// A reload: the new actor goes on from `old` (the same character): its chains swing on, and
  /// its shapes blend from where `old` drew them over kReloadBlendFrames.
  static constexpr int kReloadBlendFrames = 20;
  void carry_from(const Actor& old);
  /// When this actor was prepared with `old`'s puppet: takes over its solver's state (any grab
  /// of `old`'s let go). On the frame thread, at the swap.
  void take_puppet_from(Actor& old);
  bool shares_puppet_with(const Actor& o) const { return puppet_ == o.puppet_; }
  void carry_shapes_from(const Actor& old);

 private:
  std::string name_;
  std::shared_ptr<Puppet> puppet_;  ///< (shared only between a reload's prepare and its swap)
  Ranges r_;
  std::vector<double> solver_params_;   ///< as last given to the solver
  KeyPoseStage keys_;
  std::vector<double> key_values_;      ///< this frame's value of each of keys_.settings()
  std::vector<Vec2> detailed_v_;        ///< the solve's frame with a sculpted key's detail on it
  int worst_shape_ = -1;  ///< the shape the last reconstruct() found the most distorted (-1: none)
  PhysicsStage physics_;
  Grab grab_;
  BrushStage brush_;
  CurveStage curve_;
  ContourStage contour_;
  Mapping::Pen pen_;
  const ShowBrush* pen_spec_ = nullptr;
  const ShowCurve* curve_spec_ = nullptr;
  double pen_dt_ = 0;
  /// The tool the pen last touched with: its release (a key's recall when the pen lifts).
  ShowBrush::Release tool_release_ = ShowBrush::Spring;
  Recall tool_recall_;
  bool tool_recall_on_ = false;         ///< the next frame's poses recall tool_recall_
  std::vector<Vec2> solve_targets_;     ///< its handles', then the grab's temporary handle's
  size_t n_solve_ = 0;
  double presence_ = 1;
  std::vector<Points> blend_from_;      ///< the figure as the running show last drew it (a reload)
  int blend_left_ = 0;                  ///< frames of the blend from it still to come
};

}  // namespace mar
