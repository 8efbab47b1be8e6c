// The brush of seed 004 (feature-line manipulation), live: a pen touches a character's outline
// and drags it; the outline's points within the brush's radius move with the drag, each by the
// Gaussian weight of its distance from the touched point along the outline, and the rest of the
// character keeps its structure.
//
// On the feature frame (solve/feature_frame.h) the outline is the frame's feature lines, and the
// shape rides on them. Where the pen touches, the nearest frame vertex is the focal point; its
// contour's vertices within the radius (measured along the contour, on the rest drawing) each
// get d = exp(-s^2 / 2 sigma^2), sigma = radius / 3, and become soft targets of the solve
// (FeatureFrameSolver::set_soft: a low-rank update of the prefactored system, no
// re-factorisation). A brushed vertex's target is its rest position plus its offset, carried by
// the rigid motion its part's handles ask for (their targets' best fit from rest; a part with
// one handle: that handle's move; with none: all the character's handles'; never a secondary
// motion chain's end, which follows the pose), so the brushed
// shape rides on the part as the performer moves it — and never on where the solve put the
// part, which the brush itself pulls. The drag adds d times the pen's move to each offset. Pressure at the touch
// sets the radius. A stroke also holds a few vertices just beyond its radius where they are
// (anchors), so it bends the outline where it brushes without pulling the part away. On release
// the offsets stay (`hold`: a later stroke adds to them; when the room for kMaxPoints is full,
// the oldest strokes' vertices let go) or spring back to none over `release_seconds`. Everything a frame does is in buffers made at load.
#pragma once

#include "app/puppet.h"
#include "app/loop/handle_motion.h"
#include "app/show.h"
#include "geom/polygon.h"
#include "input/mapping.h"

#include <array>
#include <span>
#include <string>
#include <vector>

namespace mar {

/// The soft targets a show's character has room for (a brush's kMaxPoints, a curve's chain).
inline constexpr int kSoftTargets = 64;

class BrushStage {
 public:
  /// Vertices one character's brushing holds at once (the solve's extra rank is twice this).
  static constexpr int kMaxPoints = 48;
  /// Anchors a stroke sets each way beyond its radius.
  static constexpr int kAnchors = 4;

  /// Prepares the brush on `p` (its solver must be the feature frame, with room for
  /// kMaxPoints soft targets: FeatureFrameSolver::reserve_soft). Empty, or why not.
  std::string prepare(const Puppet& p);
  bool prepared() const { return frame_ != nullptr; }

  /// One frame, before the solve: the pen (`spec` its brush, or nullptr when the pen is not
  /// this character's), the canvas px per character unit, whether a grab holds the character
  /// (then the brush waits). No allocation.
  /// `targets`: this frame's handle targets (the character's, rig order).
  void step(const Mapping::Pen& pen, const ShowBrush* spec, double px_per_unit, double dt, bool grabbing,
            std::span<const Vec2> targets, Puppet& p);
  /// After the solver re-factorised (new parameters): its soft targets again.
  void restore(Puppet& p);

  struct Point {
    int v = 0;                      ///< frame vertex
    int part = 0;                   ///< its shape
    double d = 0;                   ///< this stroke's Gaussian weight (0: not in it)
    double s = 0;                   ///< this stroke's distance along the outline from the focal point
    Vec2 base = Vec2::Zero();       ///< offset from rest before this stroke, in its part's rest frame
    Vec2 offset = Vec2::Zero();     ///< offset now
    long stroke = 0;                ///< the stroke that set it last (strokes())
  };
  std::span<const Point> points() const { return {pts_.data(), size_t(n_)}; }
  bool down() const { return down_; }
  int focal() const { return focal_; }     ///< this stroke's focal frame vertex (-1: none)
  double radius() const { return radius_; }  ///< this stroke's radius, character units
  long strokes() const { return strokes_; }

 private:
  void touch(const Vec2& at, double radius, const ShowBrush& spec, Puppet& p);
  void apply(Puppet& p);  ///< the soft targets from the offsets and each part's motion

  const FeatureFrame* frame_ = nullptr;
  std::vector<int> contour_of_, at_in_contour_;  ///< per frame vertex
  std::vector<char> contour_closed_;             ///< per contour (FeatureFrame::subframes)
  HandleMotion motion_;
  std::array<Point, kMaxPoints> pts_{};
  int n_ = 0;
  std::array<int, kMaxPoints> ids_{};
  std::array<double, kMaxPoints> weights_{};
  bool down_ = false, releasing_ = false;
  bool hold_ = false;
  Vec2 pen0_ = Vec2::Zero();
  int focal_ = -1;
  double radius_ = 0, strength_ = 1, release_s_ = 0.5, release_t_ = 0;
  long strokes_ = 0;
};

}  // namespace mar
