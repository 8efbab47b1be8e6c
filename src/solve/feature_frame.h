// Feature-frame manipulation solver (seed 000 §4, ALGORITHMS.md §2).
//
// Unknowns: the q deformed frame vertices v (stored interleaved, x0 y0 x1 y1 ...).
// Energy, with e_j = v_b - v_a on line j = (a, b) and bars for rest positions:
//   E = w_r * sum_{feature lines j} 1/12 |e_j - R_j ebar_j|^2                     (Eq. 1)
//     + w_c * sum_i sum_{lines (i,k) at i} 1/3 |(v_k - v_i) - Rhat_i (vbar_k - vbar_i)|^2  (Eq. 2)
//     + w_p * sum_h |(1 - z_h) v_a + z_h v_b - c_h|^2    (complex z_h, Eqs. 3-4)
//     + eps * sum_{i in frame components without a handle} |v_i - v_i^start|^2
// Local step: every R_j, Rhat_i in closed form (2D Procrustes). Global step: one linear
// solve with a matrix that depends only on the frame and the handle *set*, factorised once
// in prepare() (sparse LDL^T); solve() warm-starts from the previous pose, runs a fixed
// number of iterations and allocates nothing.
#pragma once

#include "frame/feature_frame.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <span>
#include <string>

namespace mar {

struct SolverWeights {
  double rigidity = 1;   ///< w_r
  double coupling = 1;   ///< w_c
  double position = 100; ///< w_p
};

class FeatureFrameSolver {
 public:
  /// Factorises the system for this frame and handle set. Resets the pose to rest.
  /// Returns false with a reason when the frame is empty or the factorisation fails.
  bool prepare(const FeatureFrame& frame, std::span<const ShapeParam> handles, const SolverWeights& w,
               std::string* error = nullptr);

  /// Runs `iterations` local/global steps from the current pose toward handle `targets`
  /// (#handles). When `energies` is given (size >= iterations + 1), writes E before the
  /// first and after every iteration. Allocates nothing.
  void solve(std::span<const Vec2> targets, int iterations, std::span<double> energies = {});

  /// Moves the whole pose by the rigid motion (rotation + translation, least squares,
  /// 2D Procrustes) that best takes the handles' current positions to `targets`. The
  /// initial guess for a solve from rest: exact when the targets are a rigid motion of the
  /// rest handles, and it saves the alternation from slowly unwinding a large rotation.
  /// One handle (or coincident handles) gives a translation. Allocates nothing.
  void align_to(std::span<const Vec2> targets);

  /// Current frame vertex positions (#q).
  std::span<const Vec2> vertices() const { return v_; }
  /// Replaces the pose (e.g. a warm start from elsewhere); size must be q.
  void set_vertices(std::span<const Vec2> v);
  void reset_to_rest();

  /// E(v) with optimal rotations for v (what the alternation decreases).
  double energy(std::span<const Vec2> targets) const;
  /// E(v, R) with the given line angles (#lines, feature lines used) and vertex angles (#q).
  double energy_with_rotations(std::span<const Vec2> v, std::span<const double> line_angle,
                               std::span<const double> vertex_angle, std::span<const Vec2> targets) const;
  /// Optimal rotation angles for a pose (the local step), written into the spans.
  void optimal_rotations(std::span<const Vec2> v, std::span<double> line_angle, std::span<double> vertex_angle) const;

  size_t vertex_count() const { return v_.size(); }
  /// Non-zeros of the factor L (diagnostics, benchmarks).
  long factor_nonzeros() const { return ldlt_.matrixL().nestedExpression().nonZeros(); }
  size_t handle_count() const { return handles_.size(); }
  const FeatureFrame* frame() const { return frame_; }

 private:
  void local_step();
  void global_step(std::span<const Vec2> targets);

  const FeatureFrame* frame_ = nullptr;
  SolverWeights w_;
  std::vector<ShapeParam> handles_;
  std::vector<int> adj_begin_, adj_;  ///< CSR: neighbours of each vertex over all lines
  std::vector<Vec2> adj_rest_;        ///< vbar_k - vbar_i per CSR entry
  std::vector<int> adj_line_;         ///< feature line of each CSR entry, -1 for sewing lines
  std::vector<Vec2> line_rest_;       ///< vbar_b - vbar_a per feature line
  std::vector<char> free_;            ///< vertex is in a component without a handle
  double eps_ = 0;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt_;
  Eigen::VectorXd rhs_, x_, work_, diag_;  ///< diag_: D of the factor (vectorD() copies)
  std::vector<int> perm_, perm_inv_;  ///< factor's fill-reducing permutation and inverse
  std::vector<Vec2> v_, anchor_;
  std::vector<double> line_c_, line_s_;  ///< R_j as cos/sin (feature lines)
  std::vector<double> vert_c_, vert_s_;  ///< Rhat_i as cos/sin
  mutable std::vector<double> scratch_line_, scratch_vert_;  ///< energy() work space
};

}  // namespace mar
