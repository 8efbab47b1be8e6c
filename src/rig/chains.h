// Where a rig's [[physics]] chain is on the drawing (character/rig.h, motion/chain.h): the point
// it hangs from on its parent (the hinge the rig or the drawing gives between them, else the
// middle of where they overlap, else the dangling part's point nearest the parent), each next
// link's start likewise, and the last part's point farthest from where it hangs (or `length`
// along that way).
#pragma once

#include "character/character.h"
#include "character/rig.h"
#include "base/result.h"

#include <vector>

namespace mar {

struct ChainGeometry {
  std::vector<Vec2> rest;   ///< where it hangs, then each link's end
  std::vector<int> shapes;  ///< per link: its sub-shape
  int parent = -1;          ///< the sub-shape it hangs from
};

/// The chain's links on `ch` (its rig's joints, drawn ones included). Errors name the rig's
/// file and the chain's line: a part or `from` that is not there, a part twice.
Result<ChainGeometry> chain_geometry(const Character& ch, const Rig& rig, const RigPhysics& ph);

}  // namespace mar
