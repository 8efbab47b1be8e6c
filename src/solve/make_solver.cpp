#include "solve/make_solver.h"

#include "solve/arap.h"
#include "solve/feature_frame_method.h"
#include "solve/rigid_grid.h"

namespace mar {

bool solver_known(std::string_view name) { return name == "feature_frame" || name == "arap" || name == "rigid_grid"; }

std::unique_ptr<Solver> make_solver(std::string_view name) {
  if (name == "feature_frame") return std::make_unique<FeatureFrameMethod>();
  if (name == "arap") return std::make_unique<OutlineArap>();
  if (name == "rigid_grid") return std::make_unique<RigidGrid>();
  return nullptr;
}

}  // namespace mar
