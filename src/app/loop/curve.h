// The drawn curve of seed 001, live (`fit = "chain"`): the performer draws one stroke — the
// animator's line of action — and a chain of the character's parts (a spine, a neck and head,
// an arm, a tail) takes its curve while every part keeps its own shape.
//
// The chain is a rig chain of parts hanging from a part (rig/chains.h: where each hangs, by its
// hinge or the middle of its overlap, and the last part's far end): its axis, a polyline of
// arc length L. Each frame vertex of the chain's parts gets its place along that axis at rest:
// the arc length s of its nearest point on the axis and its signed distance n from it (the
// shape's differential coordinates about its axis, which seed 001 keeps while the shape
// follows the drawn curve). The stroke, as drawn so far, is placed with its start where the
// chain hangs now (carried by the parent part's handles, as the brush carries what it brushed);
// a vertex's target is the stroke's point at arc length s plus n along the stroke's normal
// there (beyond the drawn length, straight on along its last direction). The targets are soft
// targets of the solve (FeatureFrameSolver::set_soft, set once when the stroke is long enough to
// have a direction), so the parts turn and bend with the curve and the solve keeps their detail.
// A new stroke replaces the curve; lifting the pen keeps it (`hold`) or springs back over
// `release_seconds`. Everything a frame does is in buffers made at load.
#pragma once

#include "app/loop/handle_motion.h"
#include "app/puppet.h"
#include "app/show.h"
#include "geom/polygon.h"
#include "input/mapping.h"
#include "rig/chains.h"

#include <array>
#include <span>
#include <string>
#include <vector>

namespace mar {

class CurveStage {
 public:
  /// Points a stroke keeps (a longer one is sampled further apart as it is drawn).
  static constexpr int kMaxStroke = 512;

  /// Prepares the chain `spec` names on `p` (feature frame, with room for soft targets).
  /// Empty, or why not (naming the show's file and line).
  std::string prepare(const Puppet& p, const ShowCurve& spec, const std::string& where);
  bool prepared() const { return frame_ != nullptr; }

  /// One frame, before the solve: the pen (`spec` its curve, or nullptr when the pen is not
  /// this character's curve), whether a grab holds the character. No allocation.
  void step(const Mapping::Pen& pen, const ShowCurve* spec, double dt, bool grabbing, std::span<const Vec2> targets, Puppet& p);
  /// After step(), on the solve's targets (the character's handles, rig order): the handles on
  /// the chain's parts follow the curve too (a rig's head handle would hold the head where the
  /// line of action leans it). No allocation.
  void drive_handles(std::span<Vec2> targets) const;
  /// After the solver re-factorised: its soft targets again.
  void restore(Puppet& p);

  const ChainGeometry& chain() const { return geo_; }
  double axis_length() const { return axis_s_.empty() ? 0.0 : axis_s_.back(); }
  /// The stroke as laid (its start where the chain hangs this frame) at arc length s, and its length.
  Vec2 curve_at(double s) const;
  double stroke_length() const { return n_stroke_ > 0 ? stroke_s_[size_t(n_stroke_ - 1)] : 0.0; }
  bool active() const { return active_; }
  bool drawing() const { return down_; }
  long strokes() const { return strokes_; }
  /// A rest point near the chain laid along the curve by its place about the axis (what its
  /// parts would be, bent by the curve and nothing else: the measure of their own distortion).
  Vec2 lay(const Vec2& rest) const;
  /// The chain's soft vertices and their places about the axis at rest.
  std::span<const int> vertices() const { return {ids_.data(), ids_.size()}; }

 private:
  void project(const Vec2& x, double& s, double& n) const;  ///< its place about the rest axis
  /// That place along the curve; springing back (k > 0 of the way), along the curve eased
  /// toward the rest axis as the handles carry it (a bent chain unbends: it does not fold).
  Vec2 laid(double s, double n, double k = 0) const;
  Vec2 axis_at(double s, Vec2& tangent) const;               ///< the rest axis (straight on past its ends)
  void place(Puppet& p);  ///< the soft targets from the curve (and the spring's blend)

  const FeatureFrame* frame_ = nullptr;
  ChainGeometry geo_;
  std::vector<double> axis_s_;        ///< arc length at each axis point (geo_.rest)
  std::vector<int> ids_;              ///< soft frame vertices
  std::vector<double> weights_;
  std::vector<double> s_, n_;         ///< per soft vertex: its place about the axis at rest
  std::vector<Vec2> defect_;          ///< per soft vertex: rest minus its place's point (past the axis's ends, at corners)
  std::vector<double> hs_, hn_;       ///< per chain handle: its place
  std::vector<Vec2> hdefect_;
  RigidMotion home_;                  ///< springing: the handles' motion from rest
  HandleMotion motion_;
  std::vector<int> parent_handles_;   ///< the parent part's handles (none: the whole character's)
  std::vector<int> chain_handles_;    ///< the handles on the chain's parts (the curve drives them)
  double spring_k_ = 0;               ///< this frame's share of the way back (springing)
  Vec2 hang_ = Vec2::Zero();          ///< where the chain hangs this frame, carried by its parent's handles
  std::array<Vec2, kMaxStroke> stroke_{};
  std::array<double, kMaxStroke> stroke_s_{};
  int n_stroke_ = 0;
  double min_step_ = 1, min_length_ = 1;
  bool down_ = false, active_ = false, releasing_ = false, hold_ = true;
  double release_s_ = 0.5, release_t_ = 0;
  long strokes_ = 0;
};

}  // namespace mar
