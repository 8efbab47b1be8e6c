// Key poses of a rig ([[key]]) as frame vertices, for interpolation (src/interp).
#pragma once

#include "app/puppet.h"

namespace mar {

/// Every key of the puppet's rig, in rig order: a `targets` key solved from rest by the
/// feature frame until converged (300 iterations; other handles at rest), a `frame` key read
/// from its file (`frame_vertices` of `pose --dump`). The solver is left at rest. Errors name
/// the rig file and the key's line: a rig that is not on the feature frame, an unreadable
/// frame file, a frame with the wrong vertex count.
/// A `shapes` key (the studio's sculpt) is read from its file onto the frame; `details`, when
/// given, receives per key what its handles alone do not make of it (the key less the pose its
/// handles solve to; empty for the others), which KeyPoseStage plays on top of the solve.
Result<std::vector<Points>> solve_keys(Puppet& p, std::vector<Points>* details = nullptr);

/// A key's index by name (-1: "rest"); -2 when there is none.
int find_key(const Rig& rig, const std::string& name);

}  // namespace mar
