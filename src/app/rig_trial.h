// The automatic rig tried before it is written: its starter show for a simulated nanoKONTROL2
// played headless, then two seconds with every control back where it started. Where the rig
// from the drawing's parts tears or drifts there and its silhouette has limbs, the same
// drawing posed on the silhouette's rigid grid with the parts' limbs riding on it
// (AutoRigOptions::grid_anywhere) is tried too, and kept when it holds and moves as much.
// Rigging, not a show: never on a show's frame thread.
#pragma once

#include "character/character.h"
#include "rig/auto_rig.h"

#include <string>

namespace mar {

/// What a rig did in its starter show. Figures are % of the character's height.
struct RigTrial {
  std::string error;       ///< why it was not played (empty: it was)
  double worst_pct = -1;   ///< the worst part's distortion (RMS of its best rigid fit) over the show
  double away_pct = -1;    ///< the farthest any point is from its rest at the end
  double reach_pct = -1;   ///< the farthest any handle is from its target over the show
  double moved_pct = -1;   ///< the farthest any point went from its rest over the show
  /// Its parts keep their shape (≤ 1.5 %) and it comes back to rest (≤ 1 %).
  bool holds() const { return error.empty() && worst_pct >= 0 && worst_pct <= 1.5 && away_pct >= 0 && away_pct <= 1.0; }
};

/// Plays `ar`'s starter show for `ch`, loaded from `file` (and `mask_file`, if any) as given
/// (the rig's own paths are not used), in a folder of its own under the temporary directory,
/// removed after.
RigTrial try_rig(const AutoRig& ar, const Character& ch, const std::string& file, const std::string& mask_file = "");

/// auto_rig(ch, character, mask, options), tried as above when it is a rig from the parts: when
/// it does not hold, the grid's rig is tried and taken when it holds and moves at least half as
/// far (or half the character's height: a rig too stiff to move would hold), however far its
/// handles lag their knobs (a torn rig is worse than one that stops short). `file` and
/// `mask_file` are the drawing as this process opens it. `why` (if given) gets one line saying
/// what was tried and what it measured, the rig taken first ("parts: ..." or "grid: ..."), or
/// stays empty when nothing was tried (a rig on the grid already, or no limb in its silhouette).
AutoRig auto_rig_tried(const Character& ch, const std::string& file, const std::string& mask_file, const std::string& character,
                       const std::string& mask, const AutoRigOptions& options, std::string* why = nullptr);

}  // namespace mar
