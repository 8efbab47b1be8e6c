// The automatic rig from the silhouette, where the parts give fewer limbs (auto_rig_silhouette.cpp).
#pragma once

#include "rig/auto_rig.h"

#include <set>

namespace mar {

/// When the silhouette of the drawn shapes (all but swap and trigger `members` and what
/// `out.left_out` holds) has limbs the parts of `out` do not give, rigs `out` anew from it on the
/// rigid grid and returns true; else leaves `out` as it is. Reads `options.bones` and
/// `options.grid_anywhere`.
bool rig_from_silhouette(const Character& ch, const std::set<int>& members, double height, AutoRig& out,
                         const AutoRigOptions& options = {});

}  // namespace mar
