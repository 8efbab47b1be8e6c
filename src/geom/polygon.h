// Small polygon utilities: area, winding, containment, simplification.
#pragma once

#include "geom/types.h"

#include <span>

namespace mar {

/// Signed area of a closed polygon (positive = counter-clockwise in a y-up frame,
/// which is clockwise on a y-down screen).
double signed_area(std::span<const Vec2> ring);

/// Winding number of `p` with respect to the closed ring.
int winding_number(std::span<const Vec2> ring, const Vec2& p);

/// A rigid motion of the plane: p -> to_c + R(c, s) (p - from_c).
struct RigidMotion {
  Vec2 from_c = Vec2::Zero(), to_c = Vec2::Zero();
  double c = 1, s = 0;  ///< cos and sin of the rotation
  Vec2 apply(const Vec2& p) const { return to_c + turn(p - from_c); }
  /// Its rotation alone (of a direction or an offset); back() undoes it.
  Vec2 turn(const Vec2& v) const { return {c * v.x() - s * v.y(), s * v.x() + c * v.y()}; }
  Vec2 back(const Vec2& v) const { return {c * v.x() + s * v.y(), -s * v.x() + c * v.y()}; }
};

/// The rigid motion (rotation + translation, 2D Procrustes) that best takes `from` onto `to`
/// (the first min(sizes) points); the identity rotation when they have no spread.
RigidMotion rigid_fit(std::span<const Vec2> from, std::span<const Vec2> to);

/// The affine map that best takes `from` onto `to` (least squares over the first min(sizes)
/// points); the translation between their centroids where `from` does not span the plane (a
/// line). Allocates nothing.
Affine2 affine_fit(std::span<const Vec2> from, std::span<const Vec2> to);

/// The same over pairs given one at a time (points of several shapes).
class AffineFit {
 public:
  void add(const Vec2& from, const Vec2& to);
  Affine2 result() const;

 private:
  double n_ = 0;
  Vec2 sf_ = Vec2::Zero(), st_ = Vec2::Zero();
  Eigen::Matrix2d sff_ = Eigen::Matrix2d::Zero(), stf_ = Eigen::Matrix2d::Zero();
};

/// RMS residual of the best rigid fit (rotation + translation, 2D Procrustes) of `from`
/// onto `to` (same sizes): how much a part's shape changed, wherever it went. Allocates nothing.
double rigid_fit_rms(std::span<const Vec2> from, std::span<const Vec2> to);

/// Distance from p to segment ab.
double point_segment_distance(const Vec2& p, const Vec2& a, const Vec2& b);

/// Douglas–Peucker. Keeps the first and last point of an open polyline; for a closed
/// ring (last point not repeated) keeps two far-apart anchors. Result deviates from
/// the input by at most `tolerance`.
Points simplify_polyline(std::span<const Vec2> pts, double tolerance, bool closed);

/// Removes consecutive duplicates (and, when closed, a last point equal to the first).
void remove_duplicate_points(Points& pts, bool closed, double eps = 0.0);

}  // namespace mar
