#include "solve/solver.h"

namespace mar {

bool solver_known(std::string_view name) { return name == "feature_frame"; }

std::unique_ptr<Solver> make_solver(std::string_view name) {
  if (name == "feature_frame") return std::make_unique<FeatureFrameMethod>();
  return nullptr;
}

bool FeatureFrameMethod::prepare(Character& ch, const Rig& rig, std::span<const Vec2> handle_rest, const SolverWeights& w,
                                 std::string* error) {
  character_ = &ch;
  const FrameOptions fo = frame_options_from_rig(rig);
  refine_for_frame(ch, fo);
  frame_ = build_feature_frame(ch, fo);
  bindings_.clear();
  for (const Vec2& p : handle_rest) bindings_.push_back(bind_point(frame_, ch, p));
  return s_.prepare(frame_, bindings_, w, error);
}

bool FeatureFrameMethod::set_weights(const SolverWeights& w, std::string* error) {
  const std::vector<Vec2> pose(s_.vertices().begin(), s_.vertices().end());
  const bool ok = s_.prepare(frame_, bindings_, w, error);
  s_.set_vertices(pose);
  return ok;
}

}  // namespace mar
