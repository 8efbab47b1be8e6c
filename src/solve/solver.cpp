#include "solve/solver.h"
#include "solve/arap.h"
#include "solve/rigid_grid.h"

#include "geom/polygon.h"

#include <algorithm>

namespace mar {

void rigid_pose(std::span<const Vec2> handle_rest, std::span<const Vec2> targets, std::span<const Vec2> rest, std::span<Vec2> x,
                std::span<double> c, std::span<double> s) {
  const size_t m = std::min(targets.size(), handle_rest.size());
  RigidMotion r = rigid_fit(handle_rest.first(m), targets.first(m));
  if (m == 0 || !r.to_c.allFinite()) r = RigidMotion{};  // identity: back to rest
  for (size_t i = 0; i < rest.size() && i < x.size(); ++i) x[i] = r.apply(rest[i]);
  std::fill(c.begin(), c.end(), r.c);
  std::fill(s.begin(), s.end(), r.s);
}

bool solver_known(std::string_view name) { return name == "feature_frame" || name == "arap" || name == "rigid_grid"; }

std::unique_ptr<Solver> make_solver(std::string_view name) {
  if (name == "feature_frame") return std::make_unique<FeatureFrameMethod>();
  if (name == "arap") return std::make_unique<OutlineArap>();
  if (name == "rigid_grid") return std::make_unique<RigidGrid>();
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
