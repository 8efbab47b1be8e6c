// The feature frame (seed 000) behind the solver seam (solve/solver.h).
#pragma once

#include "solve/feature_frame.h"
#include "solve/solver.h"

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace mar {

/// The feature frame (seed 000) behind the seam; frame() and core() give its own views
/// (overlay, Table 1, frame vertices) to the commands that show them. A rig's [[rider]] (a
/// detail: an eye, a strap, a stripe) is left out of the frame and carried
/// whole by the part it is on: each frame it takes the best rigid motion of that part's points
/// about its `at`, so it can neither tear off nor bend.
class FeatureFrameMethod final : public Solver {
 public:
  std::string_view name() const override { return "feature_frame"; }
  bool prepare(Character& ch, const Rig& rig, std::span<const Vec2> handle_rest, const SolverWeights& w,
               std::string* error) override;
  /// rigidity (w_r), coupling (w_c) and position (w_p) weights.
  std::vector<SolverParameter> parameters() const override;
  bool set_parameters(std::span<const double> values, std::string* error) override;
  /// New weights, keeping the pose (re-factorises).
  bool set_weights(const SolverWeights& w, std::string* error);
  void solve(std::span<const Vec2> targets, int iterations) override { s_.solve(targets, iterations); }
  void initial_guess(std::span<const Vec2> targets) override { s_.initial_guess(targets); }
  void reset_to_rest() override { s_.reset_to_rest(); }
  void shape_points(std::vector<Points>& out) const override;
  /// The shapes of the frame posed at `v` (a key pose's, an in-between's), the riders with them.
  void place(std::span<const Vec2> v, std::vector<Points>& out) const;
  Vec2 handle_point(size_t h) const override { return eval_param(bindings_[h], s_.vertices()); }
  size_t handle_count() const override { return bindings_.size(); }
  void grab(const Vec2& rest_point) override { s_.set_extra_handle(bind_point(frame_, framed_, rest_point)); }
  void release() override { s_.clear_extra_handle(); }
  bool grabbing() const override { return s_.has_extra_handle(); }
  double energy(std::span<const Vec2> targets) const override { return s_.energy(targets); }

  const FeatureFrame& frame() const { return frame_; }
  std::span<const ShapeParam> bindings() const { return bindings_; }
  FeatureFrameSolver& core() { return s_; }
  const FeatureFrameSolver& core() const { return s_; }

 private:
  // A detail carried whole: its shape, its host's, and the points of its host it follows
  // (indices into the host's shape, with their rest positions).
  struct Carried {
    int shape = -1, host = -1;
    Vec2 at = Vec2::Zero();      ///< where it is on its host
    std::vector<int> with;       ///< shapes riding with it
    std::vector<int> follow;     ///< the host's points it takes its motion from
    Points follow_rest;          ///< their rest positions
  };
  bool prepare_riders(const Character& ch, const Rig& rig, std::string* error);

  Character framed_;             ///< the character as the frame has it (riders' shapes empty)
  std::vector<Carried> carried_; ///< in the rig's order
  std::vector<Points> carried_rest_;  ///< per shape: a riding shape's rest points (else empty)
  std::vector<int> order_;       ///< riders, each after the rider it is on
  FeatureFrame frame_;
  std::vector<ShapeParam> bindings_;
  FeatureFrameSolver s_;
  SolverWeights weights_;
};

}  // namespace mar
