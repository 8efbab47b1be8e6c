// The methods a rig may name (`solver = "..."`) and a new solver for each.
#pragma once

#include "solve/solver.h"

#include <memory>
#include <string_view>

namespace mar {

/// The methods a rig may name.
bool solver_known(std::string_view name);
/// A new solver for `name` ("feature_frame"); nullptr for an unknown name.
std::unique_ptr<Solver> make_solver(std::string_view name);

}  // namespace mar
