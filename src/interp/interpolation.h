// Structure-preserving interpolation of key poses (seed 000 §5; docs/algorithms.md §3).
//
// Triangle set (step 1): at each frame vertex with r incident lines (feature, sewing, spokes;
// not the zero-length joint pins or hinge springs), sorted by angle: r = 2 gives one triangle
// (i, n1, n2); r > 2 gives r triangles (i, n_k, n_k+1) around it. r = 1 (the end of an open
// stroke's frame, a lone sewing end): one triangle (i, n, m) with m the neighbour of n that
// makes the widest rest triangle, so every vertex with a line is in a triangle. Triangles of
// near-zero rest area (below 1e-9 of the squared diagonal) are left out.
//
// Interpolation (step 2, Alexa et al. 2000): every key is stored relative to the rest frame,
// per triangle, as the polar decomposition of the affine map rest → key, A = R(γ) S. A blend
// of keys with weights w_k is additive over rest:
//   A(w) = R(Σ w_k γ_k) (I + Σ w_k (S_k − I)),
// so all weights 0 is the rest pose, one weight 1 reproduces that key, and keys of different
// limbs add up (a knob per key does what a performer expects); a morph from key a to key b at
// t is the blend with weights 1 − t and t. Angles are unwrapped along the order the keys are
// added (each key's γ within π of the previous key's; the first key's within π of its overall
// turn, so a half turn goes one way in every triangle), so a chain of keys turns the way it
// was keyed. The frame vertices then minimise Σ_τ |B_τ(V) − A_τ(w)|²_F, B_τ the affine part
// of the map rest → V on triangle τ, plus two kinds of ties, each the blend's overall motion
// (the weighted turn of the keys' best rigid fits about the weighted centre) plus each key's
// own departure from its overall motion — exact at a key, rigid between rigid keys:
// hinge pins (the frame's zero-length joint lines) keep their offsets, and one anchor vertex
// per connected piece (a vertex in no triangle is its own piece) places the piece. The matrix
// depends on the rest frame only: factorised once per rig; every in-between is a
// back-substitution, allocation free.
#pragma once

#include "frame/feature_frame.h"
#include "solve/ldlt.h"

#include <array>
#include <span>
#include <string>
#include <vector>

namespace mar {

/// The triangle set of a frame (rest positions decide the angular order and the r = 1 case).
std::vector<std::array<int, 3>> frame_triangle_set(const FeatureFrame& f);

class KeyInterpolator {
 public:
  /// Triangle set and factorisation for `f`; false (with a message) when there is nothing to
  /// interpolate.
  bool prepare(const FeatureFrame& f, std::string* error);
  /// Adds a key (#q frame vertex positions); returns its index. Allocates.
  int add_key(std::span<const Vec2> v);
  size_t keys() const { return keys_.size(); }
  size_t triangles() const { return tris_.size(); }
  std::span<const std::array<int, 3>> triangle_set() const { return tris_; }

  /// The frame for weights over the keys (missing weights are 0), into `out` (#q). No allocation.
  void blend(std::span<const double> weights, std::span<Vec2> out);
  /// From key a to key b at t (a or b = -1: the rest pose). No allocation.
  void morph(int a, int b, double t, std::span<Vec2> out);
  /// The naive linear blend of the keys' vertices, for comparison.
  void linear_morph(int a, int b, double t, std::span<Vec2> out) const;
  /// Rotation angle of triangle `tri` in key k relative to rest (unwrapped), for tests.
  double angle(size_t k, size_t tri) const { return keys_[k].gamma[tri]; }

 private:
  struct Key {
    Points v;                                  ///< frame vertices
    std::vector<double> gamma;                 ///< per triangle: rotation angle
    std::vector<std::array<double, 3>> s;      ///< per triangle: symmetric stretch (s00, s01, s11)
    double overall = 0;                        ///< the key's overall turn (best rigid fit), unwrapped
    Vec2 centre = Vec2::Zero();                ///< centroid of its vertices
  };
  const Points& key_vertices(int k) const { return k < 0 ? rest_ : keys_[size_t(k)].v; }

  Points rest_;
  std::vector<std::array<int, 3>> tris_;
  std::vector<std::array<double, 4>> einv_;    ///< per triangle: inverse of the rest edge matrix
  std::vector<Key> keys_;
  std::vector<std::array<int, 2>> pins_;       ///< hinge pins: joint lines
  double pin_w_ = 1;
  std::vector<int> anchors_;                   ///< one vertex per connected piece
  double anchor_w_ = 1;
  Vec2 rest_centre_ = Vec2::Zero();
  PrefactoredLdlt factor_;
  std::vector<double> w_, bx_, by_;            ///< per-call buffers (weights, right-hand sides)
};

}  // namespace mar
