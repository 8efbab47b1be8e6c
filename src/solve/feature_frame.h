// Feature-frame manipulation solver (seed 000 §4, docs/algorithms.md §2).
//
// Unknowns: the q deformed frame vertices v (stored interleaved, x0 y0 x1 y1 ...).
// Energy, with e_j = v_b - v_a on line j = (a, b), bars for rest positions and k_j the
// line's weight (its parts' stiffness, a joint's pin or spring weight; FrameLine::weight):
//   E = w_r * sum_{feature lines j} k_j/12 |e_j - R_j ebar_j|^2                   (Eq. 1)
//     + w_c * sum_i sum_{lines (i,k) at i} k_ik/3 |(v_k - v_i) - Rhat_i (vbar_k - vbar_i)|^2  (Eq. 2)
//     + w_p * sum_h |(1 - z_h) v_a + z_h v_b - c_h|^2    (complex z_h, Eqs. 3-4)
//     + eps * sum_{i in frame components without a handle} |v_i - v_i^start|^2
// Local step: every R_j, Rhat_i in closed form (2D Procrustes). Global step: one linear
// solve with a matrix that depends only on the frame and the handle *set*, factorised once
// in prepare() (sparse LDL^T); solve() warm-starts from the previous pose, runs a fixed
// number of iterations and allocates nothing.
#pragma once

#include "frame/feature_frame.h"

#include <Eigen/Sparse>

#include "solve/ldlt.h"
#include <Eigen/SparseCholesky>

#include <span>
#include <vector>
#include <string>

namespace mar {

struct SolverWeights {
  double rigidity = 1;   ///< w_r
  double coupling = 1;   ///< w_c
  double position = 100; ///< w_p
  /// Anderson acceleration of the local/global map (Peng et al. 2018): history of this
  /// many iterates, 0 = the plain alternation. An accelerated iterate is kept only when the
  /// energy fell below the last accepted one; otherwise the plain step is taken and the
  /// history restarts, so the accepted energies never increase.
  int anderson = 5;
  /// Reach: a handle at the free end of a chain of hinged parts gets its target's distance
  /// from the chain's anchoring joint softly limited to what the chain spans (stretching
  /// at most `reach_stretch` of the chain's length), so a limb turns or stops instead of
  /// pulling the body out of shape. Negative: off.
  double reach_stretch = 0.04;
  /// A target that moved more than this fraction of the frame's diagonal since the last
  /// solve (a pose recall, a jump) makes solve() start from initial_guess(). <= 0: never.
  double jump = 0.08;
  /// Per handle, a scale of w_p (empty, or past its end: 1): a soft target, such as a chain's
  /// end in secondary motion (app/loop/physics.h), pulls its part without dragging the rest.
  std::vector<double> handle_weights;
  double handle_weight(size_t h) const { return h < handle_weights.size() ? handle_weights[h] : 1.0; }
};

class FeatureFrameSolver {
 public:
  /// Factorises the system for this frame and handle set. Resets the pose to rest.
  /// Returns false with a reason when the frame is empty or the factorisation fails.
  bool prepare(const FeatureFrame& frame, std::span<const ShapeParam> handles, const SolverWeights& w,
               std::string* error = nullptr);

  /// Runs `iterations` local/global steps from the current pose toward handle `targets`
  /// (#handles). When `energies` is given (size >= iterations + 1), writes E before the
  /// first iteration, then the energy of each accepted iterate (never increasing), the last
  /// being E of the returned pose. The last iteration is always a plain step. Allocates nothing.
  void solve(std::span<const Vec2> targets, int iterations, std::span<double> energies = {});

  /// A temporary extra handle (a pen grab) without re-factorising: its rank-2 term is added
  /// to the factorised system by the Woodbury identity (two triangular solves here, a 2x2
  /// correction per iteration). While set, solve() takes #handles + 1 targets, the last for
  /// this handle. Allocates nothing.
  void set_extra_handle(const ShapeParam& h);
  void clear_extra_handle() { extra_active_ = false; }
  bool has_extra_handle() const { return extra_active_; }

  /// Soft targets at frame vertices (the brush of seed 004, app/loop/brush.h): vertex
  /// `vertices[i]` is pulled toward soft_targets()[i] with weight w_p * weights[i]. Added to the
  /// factorised system by the Woodbury identity, rank 2k: set_soft() makes 2k triangular solves
  /// and a 2k x 2k Cholesky factor; each iteration adds a gather, a small triangular solve and a
  /// 2q x 2k product. At most reserve_soft()'s count, and not with an extra handle at once (the
  /// extra handle wins). Allocates nothing; false when over the count or not positive definite.
  void reserve_soft(int k);  ///< allocates (at load)
  bool set_soft(std::span<const int> vertices, std::span<const double> weights);
  std::span<Vec2> soft_targets() { return {soft_t_.data(), size_t(soft_n_)}; }
  void clear_soft() { soft_n_ = 0; }
  int soft_count() const { return soft_n_; }
  int soft_capacity() const { return soft_cap_; }

  /// Moves the whole pose by the rigid motion (rotation + translation, least squares,
  /// 2D Procrustes) that best takes the handles' current positions to `targets`. The
  /// initial guess for a solve from rest: exact when the targets are a rigid motion of the
  /// rest handles, and it saves the alternation from slowly unwinding a large rotation.
  /// One handle (or coincident handles) gives a translation. Allocates nothing.
  void align_to(std::span<const Vec2> targets);

  /// Articulated initial guess for a jump (a pose recall, a solve from rest): the frame's
  /// rigid bodies (parts joined by anything but hinges) are placed one by one — bodies with
  /// two or more handles by their best rigid fit, then across each hinge a body turns about
  /// the joint towards its handles (or follows its parent when it has none). Exact for
  /// targets that are a rigid motion of the whole, or of limbs about their joints.
  /// Replaces the pose and the rotations. Allocates nothing.
  void align_parts(std::span<const Vec2> targets);

  /// The start for a jump: of the current pose, align_to and align_parts, the one with the
  /// lowest energy for `targets`. Allocates nothing.
  void initial_guess(std::span<const Vec2> targets);

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
  /// The targets the last solve() used: the given ones, with reach applied (#handles [+1]).
  std::span<const Vec2> effective_targets() const { return {reach_targets_.data(), reach_used_}; }
  /// Solves that started from initial_guess() because the targets jumped (diagnostics).
  long jumps() const { return jumps_; }
  /// Anderson steps accepted and rejected since prepare() (diagnostics).
  long anderson_accepted() const { return aa_accepted_; }
  long anderson_rejected() const { return aa_rejected_; }
  /// Non-zeros of the factor L (diagnostics, benchmarks).
  long factor_nonzeros() const { return factor_.nonzeros(); }
  size_t handle_count() const { return handles_.size(); }
  const FeatureFrame* frame() const { return frame_; }

 private:
  void local_step();
  void vertex_rotations();
  /// Solves L D L^T y = b in place on a right-hand side in the factor's permuted order.
  void factor_solve(double* y) const;
  /// (2x2 operator) the extra handle's evaluation M y of a permuted-order vector.
  Vec2 extra_eval(const double* y) const;
  void global_step(std::span<const Vec2> targets);
  /// E(v_, current rotations): equals energy() right after local_step() + vertex_rotations().
  double current_energy(std::span<const Vec2> targets) const;
  /// Anderson mixing: takes x (the iterate) and g = G(x) in v_, writes the next iterate to
  /// v_. Returns whether it extrapolated (false: v_ stays G(x)).
  bool anderson_mix();

  void build_bodies();

  const FeatureFrame* frame_ = nullptr;
  // Rigid bodies for align_parts (built in prepare).
  struct Hinge {
    int other, v_here, v_there;
  };
  std::vector<int> body_of_;                       ///< #q
  std::vector<std::vector<int>> body_handles_;     ///< per body
  std::vector<std::vector<Hinge>> body_hinges_;    ///< per body
  std::vector<double> body_c_, body_s_;            ///< per body: rotation
  std::vector<Vec2> body_t_;                       ///< per body: x -> R x + t
  std::vector<char> body_placed_;
  std::vector<int> body_queue_;
  std::vector<Vec2> guess_v_;                      ///< 2 x #q: initial_guess candidates
  // Reach (see SolverWeights::reach_stretch), per handle: anchoring joint vertex (-1: free)
  // and the span of the chain; the clamped targets of the current solve.
  std::vector<int> reach_anchor_;
  std::vector<double> reach_min_, reach_max_;
  std::vector<Vec2> reach_targets_;
  size_t reach_used_ = 0;
  std::vector<Vec2> jump_prev_;  ///< the previous solve's given targets
  size_t jump_prev_n_ = 0;
  long jumps_ = 0;
  void apply_reach(std::span<const Vec2> targets);
  void follow_rigid_motion(std::span<const Vec2> before, std::span<const Vec2> after);
  /// v -> to + R (v - from), rotations turned by R = (c, sn).
  void move_rigidly(double c, double sn, const Vec2& from, const Vec2& to);
  // Extra handle (Woodbury): Z = A^-1 M^T in permuted order (two columns) and
  // K^-1 = (I / w_p + M Z)^-1.
  bool extra_active_ = false;
  ShapeParam extra_;
  // Soft vertex targets (Woodbury, rank 2k): Z = A^-1 U (2q x 2k, permuted order), the lower
  // Cholesky factor of K = C^-1 + U^T Z (row stride 2 soft_cap_), a 2k work vector.
  int soft_n_ = 0, soft_cap_ = 0;
  std::vector<int> soft_v_;
  std::vector<double> soft_w_;
  std::vector<Vec2> soft_t_;
  Eigen::MatrixXd soft_z_;
  std::vector<double> soft_l_, soft_r_;
  double soft_energy(std::span<const Vec2> v) const;  ///< the soft terms' sum for a pose, w_p left out
  Eigen::VectorXd extra_z0_, extra_z1_;
  double extra_k_[4] = {0, 0, 0, 0};
  SolverWeights w_;
  std::vector<ShapeParam> handles_;
  std::vector<int> adj_begin_, adj_;  ///< CSR: neighbours of each vertex over all lines
  std::vector<Vec2> adj_rest_;        ///< vbar_k - vbar_i per CSR entry
  std::vector<int> adj_line_;         ///< feature line of each CSR entry, -1 for sewing lines
  std::vector<double> adj_w_;         ///< weight of each CSR entry's line
  std::vector<Vec2> line_rest_;       ///< vbar_b - vbar_a per feature line
  std::vector<double> line_rest_n2_;  ///< |vbar_b - vbar_a|^2 per feature line
  std::vector<double> line_w_;        ///< weight per feature line (0 for degenerate)
  std::vector<double> adj_rest_n2_;   ///< per vertex: sum of w |vbar_k - vbar_i|^2 over its CSR entries
  double e_lines_ = 0, e_spokes_ = 0; ///< energy terms summed by the last rotation passes
  bool any_free_ = false;
  std::vector<char> free_;            ///< vertex is in a component without a handle
  double eps_ = 0;
  PrefactoredLdlt factor_;
  Eigen::VectorXd rhs_, x_, work_;
  std::vector<int> perm_, perm_inv_;  ///< factor's fill-reducing permutation and inverse
  std::vector<Vec2> v_, anchor_;
  std::vector<double> line_c_, line_s_;  ///< R_j as cos/sin (feature lines)
  std::vector<double> vert_c_, vert_s_;  ///< Rhat_i as cos/sin
  mutable std::vector<double> scratch_line_, scratch_vert_;  ///< energy() work space
  // Anderson history (columns of 2q), preallocated in prepare().
  Eigen::MatrixXd aa_dF_, aa_dG_;
  Eigen::VectorXd aa_x_, aa_g_, aa_f_, aa_prev_g_, aa_prev_f_, aa_accept_g_;
  double aa_gram_[16 * 16] = {};  ///< dF^T dF (row stride 16)
  int aa_count_ = 0, aa_head_ = 0;
  long aa_accepted_ = 0, aa_rejected_ = 0;
};

}  // namespace mar
