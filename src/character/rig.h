// Rig file (TOML, config/rigs/): which character, its handles, sewing edits, frame
// sampling, solver iterations and weights. Validated once at load; errors name file:line.
//
//   character = "../characters/butterfly.svg"   # relative to the rig file
//   solver = "feature_frame"                     # the deformation method (solve/solver.h)
//   iterations = 12
//   [weights]   rigidity = 1.0  coupling = 1.0  position = 100.0
//   [sampling]  mode = "features" | "uniform"   interval = 20.0   (uniform: arc length)
//   [[handle]]  name = "head"   rest = [200.0, 135.0]
//   [[sewing]]  action = "add" | "delete" | "move"   from = [x, y]   to = [x, y]
//               (move also: new_from = [x, y]   new_to = [x, y])
//   [feature_frame]  anderson = 5   joints = "auto" | "none"   stiffness = "auto" | "none"
//   [[joint]]   at = [x, y]   parts = ["arm", "body"]   stiffness = 0.3   kind = "hinge" | "weld"
//               (a hinge needs `at` or `parts`; a weld needs `parts`)
//   [[part]]    id = "torso"   stiffness = 4.0
//   [[rider]]   part = "arm"   on = "torso"   at = [x, y]   handle = "hand"   with = ["sleeve"]
//   [[bone]]    handle = "leg"   at = [x, y]   axis = [[x, y, half-width], ...]   band = 0
//               (rider and bone: solver = "rigid_grid"; solve/rigid_grid.h)
//   [[swap]]    name = "mouth"   members = ["mouth-a", "mouth-o"]   default = "mouth-a"
//   [[trigger]] name = "blink"   shapes = ["eyes-shut"]
//   [[physics]] name = "hair"   parts = ["hair-1", "hair-2"]   from = "head"   model = "pendulum" | "spring"
//               frequency = 1.5   damping = 0.15   inertia = 1   mass = 1   gravity = [0, 980]   wind = [0, 0]
//               gust = 0   mix = 1   limit = 0   weight = 0.2   length = 0   handle = "tail-top"
//               (secondary motion: motion/chain.h)
#pragma once

#include "character/character.h"

#include <iosfwd>
#include <string>
#include <vector>

namespace mar {

struct RigHandle {
  std::string name;
  Vec2 rest = Vec2::Zero();
  bool physics = false;  ///< a [[physics]] chain's link end (added for a show, not in the file)
};

struct RigSewing {
  enum Action { Add, Delete, Move } action = Add;
  Vec2 from = Vec2::Zero(), to = Vec2::Zero();
  Vec2 new_from = Vec2::Zero(), new_to = Vec2::Zero();
  int line = 0;  ///< line in the rig file (0 when made in code)
};

struct RigJoint {
  bool has_at = false;
  Vec2 at = Vec2::Zero();
  std::string part_a, part_b;  ///< both empty: the two topmost closed parts at `at`
  double stiffness = -1;       ///< < 0: the default hinge stiffness
  bool weld = false;
  int line = 0;
};

struct RigPart {
  std::string id;
  double stiffness = 1;
  int line = 0;
};

/// A region of local stiffness for the rigid grid: nodes within `radius` of `center` get
/// weight `weight` (w_i); a named one is a live setting `solver.stiffness.NAME`.
struct RigStiffness {
  std::string name;
  Vec2 center = Vec2::Zero();
  double radius = 0, weight = 1;
  int line = 0;
};

/// A part that rides on the rigid grid (`[[rider]]`, solver = "rigid_grid"): taken out of the
/// grid's mesh, it turns whole about its hinge `at`, which follows what it hangs from (`on`: a
/// part of another rider, or else the grid under `at`); its handle, if any, and those on what
/// hangs on it turn it toward their targets, and the shapes `with` it (details, outlines, a
/// hand) ride along. A rig mixes parts and
/// silhouette this way: a limb drawn as a part of its own stays rigid and hinged, a limb inside
/// one shape bends in the grid. A `still` one (scenery: a backdrop, a ground shadow) is out of
/// the mesh and stays where it is drawn: in the mesh, a rectangle under the whole drawing joined
/// every limb to every other through it and turned with them.
struct RigRider {
  std::string part;               ///< sub-shape id
  std::string on;                 ///< sub-shape id it hangs from ("" : the grid)
  Vec2 at = Vec2::Zero();         ///< the hinge
  std::string handle;             ///< a [[handle]] name ("" : it keeps the turn of what it hangs from)
  std::vector<std::string> with;  ///< sub-shape ids riding on it
  bool still = false;             ///< it hangs on nothing and never moves (no on, at or handle)
  int line = 0;
};

/// A limb inside one shape that turns whole (`[[bone]]`, solver = "rigid_grid"): the points of
/// the drawing within the limb's half-width of its medial axis (from its free end to its joint)
/// turn as one about the joint `at`, toward its handle's target, while the grid carries the
/// joint and the rest of the figure; across `band` on each side of the joint they turn part
/// of the way. A leg inside its body's shape then turns at its hip as a leg drawn as a part of
/// its own does, where the grid alone bends it like a beam.
struct RigBone {
  std::string handle;           ///< a [[handle]] name ("" : it keeps the turn of the grid at its joint)
  Vec2 at = Vec2::Zero();       ///< the joint
  std::vector<Vec2> axis;       ///< its medial axis, from the free end to the joint
  std::vector<double> radius;   ///< its half-width at each point of `axis`
  double band = 0;              ///< half the blend's length along the axis (0: the half-width at the joint)
  int line = 0;
};

/// A key pose (`[[key]]`): handle targets solved once at load, or a saved frame (the
/// `frame_vertices` of `pose --dump`, a path relative to the rig).
/// How far apart a sculpted character's frame points may be along an outline, a fraction of its
/// diagonal: a brush's (app/loop/brush.h) or a sculpted key's (RigKey::shapes). The features
/// alone leave an ellipse a handful of points, too few for a brushed profile.
inline constexpr double kSculptSpacing = 0.01;

struct RigKey {
  std::string name;
  std::vector<std::pair<std::string, Vec2>> targets;  ///< handle name, target (others at rest)
  std::string frame;
  /// A sculpted key (the studio's brush or curve): a JSON file of every shape's outline as posed,
  /// by shape id, per contour, each point's rest and where it is ({"shapes": {"ID": [[[rest x,
  /// rest y, x, y], ...], ...]}}), which fits a frame of any density and a drawing flattened at
  /// any size. A rig with one has the finer frame (kSculptSpacing), so the sculpted detail plays.
  std::string shapes;
  int line = 0;
};

/// A swap set (`[[swap]]`): sub-shapes of which one shows at a time (mouth shapes, hands);
/// the others are hidden but deform with the rest, so a swap never jumps.
struct RigSwap {
  std::string name;
  std::vector<std::string> members;  ///< sub-shape ids
  int default_member = 0;            ///< index into members
  int line = 0;
};
/// A trigger (`[[trigger]]`): sub-shapes hidden until it fires (a blink, a blush). A shape that
/// is also a swap member takes its set over while the trigger is on.
struct RigTrigger {
  std::string name;
  std::vector<std::string> shapes;  ///< sub-shape ids
  int line = 0;
};

/// A chain of dangling parts (`[[physics]]`, motion/chain.h): the parts hang from `from` (a
/// part, or a handle: the part under it), each from the one before; their ends follow a
/// pendulum or spring simulation in a show.
struct RigPhysics {
  std::string name;
  std::vector<std::string> parts;  ///< sub-shape ids, the one nearest `from` first
  std::string from;                ///< a sub-shape id or a handle name
  bool spring = false;             ///< model = "spring" (the length springs too)
  double frequency = -1;           ///< Hz (< 0: the model's default: pendulum 0, spring 2)
  double damping = 0.15, inertia = 1, mass = 1;
  bool has_gravity = false;        ///< gravity given: it replaces the show's
  Vec2 gravity = Vec2::Zero();
  Vec2 wind = Vec2::Zero();        ///< added to the show's
  double gust = 0;                 ///< wind noise amplitude (smooth, deterministic)
  double mix = 1, limit = 0;
  /// How hard its ends pull, a fraction of the rig's position weight (soft targets: the parts
  /// it moves keep their shape, and what it hangs from is barely dragged).
  double weight = 0.2;
  double length = 0;               ///< the last link's length (0: from the drawing)
  /// A rig handle the chain's end drives in a show (empty: a handle of the rig's on the last
  /// part, if any, else a new one).
  std::string handle;
  int line = 0;
};

struct Rig {
  std::string path;       ///< the rig file (for messages and relative paths)
  std::string character;  ///< as written in the file
  std::string mask;       ///< a PNG character's mask (non-black = figure), as written; empty: its alpha
  std::string solver = "feature_frame";  ///< the method (checked by the solver factory)
  int solver_line = 0;    ///< line of `solver` in the file (0: not given)
  int iterations = 12;
  double w_rigidity = 1, w_coupling = 1, w_position = 100;
  bool uniform_sampling = false;
  double interval = 0;  ///< uniform sampling interval, character units (0 = automatic)
  /// > 0: frame points at most this far apart along an outline (a fraction of the diagonal;
  /// FrameOptions::max_spacing): kSculptSpacing for a rig with a sculpted key or a show whose
  /// [[brush]] or [[curve]] sculpts the character.
  double max_spacing = 0;
  std::vector<RigHandle> handles;
  std::vector<RigSewing> sewing;
  int anderson = 5;           ///< Anderson acceleration history (0: off)
  bool auto_joints = true;    ///< detect hinges where parts overlap at one end
  bool auto_stiffness = true; ///< bigger parts stiffer
  std::vector<RigJoint> joints;
  std::vector<RigPart> parts;
  // The rigid grid (solver = "rigid_grid"): [grid] and [[stiffness]].
  double grid_cell = 0;        ///< cell size, character units (0: the diagonal / 40)
  int grid_half_width = 3;     ///< w, whole cells: the global stiffness
  /// Every stride-th grid node centres a region that counts (0: about w / 2; 1: every node, as
  /// seed 003). See solve/rigid_grid.h.
  int grid_stride = 0;
  double grid_rigidity = 6, grid_junction = 6;  ///< w_r, w_s (seed 003: 6, 1 with its Eq. 4 term)
  /// "triangles": each junction triangle as rigid as possible; "mvc": seed 003's Eq. 4
  /// (mean-value coordinates + rest lengths along the current directions).
  std::string grid_junction_term = "triangles";
  std::vector<RigStiffness> stiffness;
  std::vector<RigRider> riders;  ///< parts riding on the rigid grid
  std::vector<RigBone> bones;    ///< limbs inside one shape turning whole on the rigid grid
  std::vector<RigKey> keys;
  std::vector<RigSwap> swaps;
  std::vector<RigTrigger> triggers;
  std::vector<RigPhysics> physics;

  /// The character path resolved against the rig file's folder.
  std::string character_path() const;
  /// A path the rig gives (a character, a mask, a key's frame file) resolved against the rig
  /// file's folder; an absolute one as is.
  std::string beside(const std::string& file) const;
  /// The mask path resolved the same way (empty when the rig names none).
  std::string mask_path() const;
  /// Index of the handle with this name, or -1.
  int find_handle(const std::string& name) const;
};

Rig default_rig();

/// The frame spacing a rig's own keys ask for: kSculptSpacing with a sculpted key, else 0.
inline double sculpt_spacing(const Rig& r) {
  for (const RigKey& k : r.keys)
    if (!k.shapes.empty()) return kSculptSpacing;
  return 0;
}

/// Loads and validates a rig. Errors: "file:line: what is wrong".
Result<Rig> load_rig(const std::string& path);
Result<Rig> parse_rig(std::string_view text, const std::string& path);

/// A [[bone]] table (both rig writers).
void write_bone(std::ostream& o, const RigBone& b);
/// TOML text of a rig; parse_rig(write_rig(r)) gives r back.
std::string write_rig(const Rig& rig);
/// One [[key]] table as TOML (what `pose --save-key` appends to a rig).
std::string key_toml(const RigKey& k);

}  // namespace mar
