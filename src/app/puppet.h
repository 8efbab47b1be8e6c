// A rigged character ready to pose: the character (refined for its frame), the rig, the
// feature frame, handle bindings, the prefactored solver and render meshes.
#pragma once

#include "character/rig.h"
#include "render/tessellate.h"
#include "solve/feature_frame.h"

#include <memory>
#include <string>

namespace mar {

struct Puppet {
  Character character;
  Rig rig;
  FeatureFrame frame;
  std::vector<ShapeParam> bindings;  ///< one per rig handle
  FeatureFrameSolver solver;
  CharacterMesh mesh;
  std::vector<Points> shapes;        ///< deformed shape points (rest after load)
  double prefactor_ms = 0;           ///< time of FeatureFrameSolver::prepare
  std::vector<Vec2> rest_targets() const;
  /// Rebuilds `shapes` from the solver's current frame vertices.
  void reconstruct();
};

/// Loads the rig, then the character (`character_path`, or the rig's own when empty).
/// Errors are bad input (file:line).
Result<std::unique_ptr<Puppet>> load_puppet(const std::string& character_path, const std::string& rig_path);

}  // namespace mar
