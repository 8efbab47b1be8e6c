// The outline ARAP baseline (docs/algorithms.md §5; Sorkine & Alexa 2007): as-rigid-as-possible
// on one constrained triangulation of the whole character — every contour a constraint,
// the faces inside some closed part kept, so overlapping parts are one piece as a single
// outline makes them. Per-vertex rotations over cotangent-weighted one-rings (local step),
// one prefactored linear solve for x and y (global step); handles are soft constraints at
// their rest points' barycentric coordinates. It is the method the seeds compare against,
// and the familiar behaviour for users who know ARAP puppet tools.
#pragma once

#include "solve/ldlt.h"
#include "solve/solver.h"

#include <array>

namespace mar {

class OutlineArap final : public Solver {
 public:
  std::string_view name() const override { return "arap"; }
  bool prepare(Character& ch, const Rig& rig, std::span<const Vec2> handle_rest, const SolverWeights& w,
               std::string* error) override;
  /// position (the handles' weight against the cotangent energy).
  std::vector<SolverParameter> parameters() const override;
  bool set_parameters(std::span<const double> values, std::string* error) override;
  void solve(std::span<const Vec2> targets, int iterations) override;
  void initial_guess(std::span<const Vec2> targets) override;
  void reset_to_rest() override;
  void shape_points(std::vector<Points>& out) const override;
  Vec2 handle_point(size_t h) const override { return eval(handles_[h]); }
  size_t handle_count() const override { return handles_.size(); }
  void grab(const Vec2& rest_point) override;
  void release() override { grab_active_ = false; }
  bool grabbing() const override { return grab_active_; }

  /// The mesh (rest positions and counter-clockwise triangles), for tests and overlays.
  const Points& rest() const { return rest_; }
  const Points& vertices() const { return x_; }
  std::span<const std::array<int, 3>> triangles() const { return tris_; }
  /// The ARAP energy of the current pose (without the handle term).
  double energy() const;
  /// With the handle term for `targets` (Solver::energy).
  double energy(std::span<const Vec2> targets) const override;

 private:
  /// A point of the rest mesh as barycentric coordinates in one triangle.
  struct Bary {
    int v[3] = {0, 0, 0};
    double w[3] = {1, 0, 0};
  };
  Bary locate(const Vec2& p) const;
  Vec2 eval(const Bary& b) const { return b.w[0] * x_[size_t(b.v[0])] + b.w[1] * x_[size_t(b.v[1])] + b.w[2] * x_[size_t(b.v[2])]; }
  bool factorise(std::string* error);
  void local_step();
  void global_step(std::span<const Vec2> targets);

  Points rest_, x_;
  std::vector<std::array<int, 3>> tris_;
  std::vector<int> nb_start_, nb_;  ///< one-ring (CSR); each undirected edge appears in both rings
  std::vector<double> nb_w_;        ///< cotangent weight of the edge
  std::vector<double> rc_, rs_;     ///< per-vertex rotation (cos, sin)
  std::vector<double> pull_;        ///< pull toward the current pose of a part no handle reaches (0: held)
  std::vector<std::vector<Bary>> binds_;  ///< per shape, per point
  std::vector<Bary> handles_;
  Points handle_rest_;
  double position_ = 100;
  /// Per handle, a scale of w_p (SolverWeights::handle_weights: a chain's end is a soft target).
  std::vector<double> handle_w_;
  double handle_w(size_t h) const { return h < handle_w_.size() ? handle_w_[h] : 1.0; }
  PrefactoredLdlt factor_;
  std::vector<double> bx_, by_;     ///< right-hand sides in the factor's order
  // Grab: one extra soft constraint by Sherman-Morrison (z = K^-1 a, in the factor's order).
  bool grab_active_ = false;
  Bary grab_;
  RankOneUpdate grab_update_;
};

}  // namespace mar
