// The automatic rig: from a drawing alone, a rig that loads and performs with no edits.
//
// The parts (closed, filled sub-shapes) and where they overlap make a tree hanging from the
// body, the part most others attach to. A part attached to its parent near one end of its own
// long axis is a limb: a hinge where it enters its parent (the middle of the two points where
// their outlines cross: where the limb's medial axis goes in), followed down chains (upper arm,
// forearm, hand), and a handle at the free end of the last. The body gets a handle, and so does
// a big part that is not a limb (a head). Parts mostly inside another (eyes, a pocket) and
// small ones are details: they follow their parent.
//
// Names are hints, never requirements (Character Animator's way, case-insensitive, from ids and
// Inkscape labels): head/face, body/torso, arm, hand, leg, foot, tail, ear, hair, left/right
// name and classify parts; `mouth-*` shapes make a swap set `mouth`, any other group whose
// children are alternatives (one showing, the others display: none) a swap set after the group,
// eyes with open and closed
// (or shut) shapes a swap set `eyes` and a trigger `blink`.
#pragma once

#include "character/character.h"
#include "character/rig.h"

#include <string>
#include <vector>

namespace mar {

struct AutoRigPart {
  enum Kind { Body, Head, Limb, Detail };
  int shape = -1;   ///< index into Character::shapes
  int parent = -1;  ///< index into AutoRig::parts (-1: the body, or a part attached to nothing)
  Kind kind = Detail;
  bool has_joint = false;  ///< a limb's hinge
  Vec2 joint = Vec2::Zero();
  std::vector<Vec2> path;  ///< a limb's medial axis, from its free end
  std::vector<double> path_radius;  ///< its half-width at each point of `path` (a limb of the silhouette; else empty)
  std::string handle;      ///< the handle it carries ("" for none)
  std::string why;         ///< one line for the rig's comments
};

/// A shape the rig leaves out of the character's tree (a background disc, a ground shadow):
/// it stays where it is drawn.
struct AutoRigLeftOut {
  int shape = -1;
  std::string why;
};

struct AutoRig {
  Rig rig;  ///< handles, joints, swaps and triggers (character as given)
  std::vector<AutoRigPart> parts;
  std::vector<AutoRigLeftOut> left_out;
  std::vector<std::string> notes;  ///< what it could not do, for the user
  std::vector<std::string> notes_sewing;  ///< why each of rig.sewing is there
};

struct AutoRigOptions {
  /// Where the silhouette has limbs the parts miss, rig from it (auto_rig_silhouette.h); and a
  /// shape drawn in pieces is rigged by their outline together (both draw and trace).
  bool silhouette = true;
  bool head_hinge = true;  ///< a head hanging from the body turns about its neck
  /// A long, straight, free limb the silhouette finds inside one shape turns whole at its joint
  /// ([[bone]]; `rig --bones`); else the grid bends it. Off unless asked: measured on the
  /// benchmark's drawings it helps figures' straight limbs and does not help as many others
  /// (docs/auto-rig.md).
  bool bones = false;
  /// A detail on a part (an eye, a strap, a stripe, a fill inside its outline) rides on it
  /// whole ([[rider]] on the feature frame) rather than in the frame sewn to it, where a turn of
  /// its part could tear it off. Off for the drawn joints a hand-written rig takes
  /// (add_drawn_joints): its details are in its frame.
  bool ride_details = true;
  /// Pose the drawing on its silhouette's rigid grid, the parts' limbs riding on it, wherever
  /// the silhouette has a limb at all; else the grid takes over only where the silhouette finds
  /// two limbs the parts miss. `marionette rig` tries this rig on its starter show when the
  /// parts' rig tears or drifts there (app/rig_trial.h).
  bool grid_anywhere = false;
};

/// Rigs `ch`; `character` is written into the rig as is (relative to where the rig will be).
AutoRig auto_rig(const Character& ch, const std::string& character, const std::string& mask = "", const AutoRigOptions& options = {});

/// The rig as commented TOML, each handle, hinge, swap and trigger with why it is there.
std::string write_auto_rig(const AutoRig& a, const Character& ch);

/// What a rig gets from the drawing where it states nothing (a plain rig: handles only): for
/// each limb that is a part, whose pair of parts the rig names in no [[joint]] (and no joint of
/// the rig's stands near), the automatic rig's hinge at the drawn joint; and the automatic
/// rig's sewing that follows the parts' tree. Returns how many hinges it added.
int add_drawn_joints(const Character& ch, Rig& rig);

/// Words of a name, lower case: "armRight_2" -> {"arm", "right", "2"}.
std::vector<std::string> name_words(const std::string& name);

}  // namespace mar
