// The drawn curve of seed 001 fitting an outline (`[[curve]] fit = "contour"`): the performer
// redraws a line of the character — a cheek, a back, a fin — and the outline segment the stroke
// runs along takes the stroke's shape, its finer detail added back on top.
//
// Where the pen goes down, the nearest outline vertex of the curve's parts (any part when it
// names none) starts the segment; as the stroke is drawn, the vertex of that contour nearest the
// pen ends it (the shorter way round a closed contour, at most kMaxPoints vertices). The
// segment's shape at rest is a smooth base (its least-squares quadratic in arc fraction) plus
// detail, each vertex's offset from the base in the base's tangent and normal there. Each vertex at arc fraction u of
// the segment targets the stroke's point at fraction u of its length, plus its detail in the
// stroke's tangent and normal: the outline takes the stroke's course and keeps its bumps. The
// targets are soft targets of the solve (FeatureFrameSolver::set_soft), with kAnchors vertices
// each way beyond the segment held where they were, so the rest of the part keeps its shape.
// Lifting the pen keeps the fitted shape riding on its part (`hold`, carried by the part's
// handles as the brush carries what it brushed), or springs it back over `release_seconds`.
// A new stroke replaces the fit. Everything a frame does is in buffers made at load.
#pragma once

#include "app/loop/handle_motion.h"
#include "app/puppet.h"
#include "app/show.h"
#include "input/mapping.h"

#include <array>
#include <span>
#include <string>
#include <vector>

namespace mar {

class ContourStage {
 public:
  static constexpr int kMaxPoints = 40;  ///< segment vertices (with the anchors, the solve's soft targets)
  static constexpr int kAnchors = 4;
  static constexpr int kMaxStroke = 512;

  /// Prepares the outlines of `spec`'s parts (all when it names none) on `p`. Empty, or why not.
  std::string prepare(const Puppet& p, const ShowCurve& spec, const std::string& where);
  bool prepared() const { return frame_ != nullptr; }

  /// One frame, before the solve (as CurveStage::step). No allocation.
  void step(const Mapping::Pen& pen, const ShowCurve* spec, double dt, bool grabbing, std::span<const Vec2> targets, Puppet& p);
  /// After the solver re-factorised: its soft targets again.
  void restore(Puppet& p);

  bool active() const { return n_ > 0; }
  bool drawing() const { return down_; }
  long strokes() const { return strokes_; }
  /// The segment's frame vertices, from the stroke's start (then the anchors).
  std::span<const int> segment() const { return {ids_.data(), size_t(seg_)}; }
  /// The stroke as drawn (character units).
  std::span<const Vec2> stroke() const { return {stroke_.data(), size_t(n_stroke_)}; }
  /// A segment vertex's detail: its offset from the smooth base, along and across it.
  Vec2 detail(int i) const { return detail_[size_t(i)]; }

 private:
  /// The outline vertex nearest `at` within `reach` (of `contour`, or any allowed one: -1). -1: none.
  int nearest(const Vec2& at, int contour, std::span<const Vec2> v, double reach) const;
  void choose(int end, Puppet& p);  ///< the segment from a_ to `end` on contour c_, and its soft targets
  void place(Puppet& p);            ///< the soft targets from the stroke (drawing) or the held offsets
  Vec2 stroke_at(double s, Vec2& tangent) const;

  const FeatureFrame* frame_ = nullptr;
  std::vector<int> contour_of_, at_in_contour_;
  std::vector<char> contour_closed_, allowed_;   ///< per contour
  HandleMotion motion_;
  std::vector<double> rest_s_;                   ///< per frame vertex: arc length along its contour at rest
  std::vector<Vec2> seen_;                       ///< the frame as it was at the touch
  double reach_ = 1;                             ///< how near an outline a stroke must start
  std::array<int, kMaxPoints + 2 * kAnchors> ids_{};
  std::array<double, kMaxPoints + 2 * kAnchors> weights_{};
  std::array<double, kMaxPoints> u_{};           ///< arc fraction along the segment
  std::array<Vec2, kMaxPoints> detail_{};        ///< (along, across) the base
  std::array<Vec2, kMaxPoints + 2 * kAnchors> held_{};   ///< where each was at the touch (anchors), or its offset in its part's rest frame (held)
  int n_ = 0, seg_ = 0, c_ = -1, a_ = -1, b_ = -1, part_ = -1;
  std::array<Vec2, kMaxStroke> stroke_{};
  std::array<double, kMaxStroke> stroke_s_{};
  int n_stroke_ = 0;
  double min_step_ = 1, strength_ = 1;
  bool down_ = false, releasing_ = false, hold_ = true;
  double release_s_ = 0.5, release_t_ = 0, spring_k_ = 1;
  long strokes_ = 0;
};

}  // namespace mar
