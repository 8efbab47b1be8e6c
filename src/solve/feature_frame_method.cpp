#include "solve/feature_frame_method.h"

namespace mar {

bool FeatureFrameMethod::prepare(Character& ch, const Rig& rig, std::span<const Vec2> handle_rest, const SolverWeights& w,
                                 std::string* error) {
  character_ = &ch;
  const FrameOptions fo = frame_options_from_rig(rig);
  refine_for_frame(ch, fo);
  frame_ = build_feature_frame(ch, fo);
  bindings_.clear();
  for (const Vec2& p : handle_rest) bindings_.push_back(bind_point(frame_, ch, p));
  weights_ = w;
  return s_.prepare(frame_, bindings_, w, error);
}

std::vector<SolverParameter> FeatureFrameMethod::parameters() const {
  return {{"rigidity", weights_.rigidity, 1e-6, 1e9}, {"coupling", weights_.coupling, 1e-6, 1e9},
          {"position", weights_.position, 1e-6, 1e9}};
}

bool FeatureFrameMethod::set_parameters(std::span<const double> v, std::string* error) {
  if (v.size() != 3) {
    if (error) *error = "feature_frame has 3 parameters (rigidity, coupling, position)";
    return false;
  }
  SolverWeights w = weights_;
  w.rigidity = v[0];
  w.coupling = v[1];
  w.position = v[2];
  return set_weights(w, error);
}

bool FeatureFrameMethod::set_weights(const SolverWeights& w, std::string* error) {
  const std::vector<Vec2> pose(s_.vertices().begin(), s_.vertices().end());
  const bool ok = s_.prepare(frame_, bindings_, w, error);
  if (ok) weights_ = w;
  s_.set_vertices(pose);
  return ok;
}

}  // namespace mar
