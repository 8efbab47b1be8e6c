// The automatic rig as commented TOML (write_auto_rig).
#include "rig/auto_rig.h"
#include "rig/rig_text.h"

#include <cstdio>
#include <sstream>

namespace mar {
namespace {

std::string point_toml(const Vec2& p) { return toml_point(p.x(), p.y()); }
std::string q(const std::string& s) { return toml_string(s); }

}  // namespace

std::string write_auto_rig(const AutoRig& a, const Character& ch) {
  std::ostringstream o;
  const Rig& r = a.rig;
  o << "# Automatic rig (marionette rig) for " << r.character << ".\n"
    << "# Every handle, hinge, swap set and trigger below says why it is there; edit freely.\n";
  for (const std::string& n : a.notes) o << "# Note: " << n << "\n";
  o << "character = " << q(r.character) << "\n";
  if (!r.mask.empty()) o << "mask = " << q(r.mask) << "\n";
  o << "iterations = " << r.iterations << "\n";
  if (r.solver != "feature_frame")
    o << (r.bones.empty() ? "# Posed by the topology-aware rigid grid (seed 003): a limb bends inside one shape, softest\n"
                            "# at the [[stiffness]] regions below (its joints and bends).\n"
                          : "# Posed by the topology-aware rigid grid (seed 003); a limb inside one shape turns whole at its\n"
                            "# joint (its [[bone]] below), softest there.\n")
      << "solver = " << q(r.solver) << "\n";
  auto part_of_handle = [&](const std::string& h) -> const AutoRigPart* {
    for (const AutoRigPart& p : a.parts)
      if (p.handle == h) return &p;
    return nullptr;
  };
  o << "\n# ---- handles: what a control or a pen moves ----\n";
  for (const RigHandle& h : r.handles) {
    const AutoRigPart* p = part_of_handle(h.name);
    if (p) {
      const std::string& id = ch.shapes[size_t(p->shape)].id;
      o << "\n# " << id << ": " << p->why << (p->kind == AutoRigPart::Limb ? "; the handle at its free end" : "") << ".\n";
    }
    o << "[[handle]]\nname = " << q(h.name) << "\nrest = " << point_toml(h.rest) << "\n";
  }
  if (!r.joints.empty()) o << "\n# ---- hinges, where each limb goes into its parent (the drawn joint) ----\n";
  for (const RigJoint& j : r.joints) {
    if (j.weld) o << "\n# " << j.part_a << " and " << j.part_b << ": pieces of one group, welded: they move as one part";
    o << "\n[[joint]]\nat = " << point_toml(j.at) << "\nparts = [" << q(j.part_a) << ", " << q(j.part_b) << "]\nkind = \""
      << (j.weld ? "weld" : "hinge") << "\"\n";
  }
  if (!r.stiffness.empty()) o << "\n# ---- softer where each limb joins and bends: it turns there ----\n";
  for (const RigStiffness& s : r.stiffness)
    o << "\n[[stiffness]]\nname = " << q(s.name) << "\ncenter = " << point_toml(s.center) << "\nradius = " << toml_number(s.radius)
      << "\nweight = " << toml_number(s.weight) << "\n";
  if (!r.riders.empty())
    o << (r.solver == "rigid_grid" ? "\n# ---- parts that ride whole on the grid, turning at their drawn joint (toward their handle) ----\n"
                                   : "\n# ---- details that ride whole on their part (an eye, a strap, a fill in its outline): they turn with it ----\n");
  for (const RigRider& d : r.riders) {
    o << "\n[[rider]]\npart = " << q(d.part) << "\n";
    if (!d.on.empty()) o << "on = " << q(d.on) << "\n";
    if (d.still) o << "still = true  # scenery: out of the grid, where it is drawn\n";
    else o << "at = " << point_toml(d.at) << "\n";
    if (!d.handle.empty()) o << "handle = " << q(d.handle) << "\n";
    if (!d.with.empty()) {
      o << "with = [";
      for (size_t k = 0; k < d.with.size(); ++k) o << (k ? ", " : "") << q(d.with[k]);
      o << "]\n";
    }
  }
  if (!r.bones.empty())
    o << "\n# ---- limbs inside one shape, turning whole at their joint (toward their handle); the grid carries the rest ----\n";
  for (const RigBone& b : r.bones) write_bone(o, b);
  if (!r.sewing.empty()) o << "\n# ---- sewing that follows the parts' tree ----\n";
  for (size_t k = 0; k < r.sewing.size(); ++k) {
    const RigSewing& e = r.sewing[k];
    if (k < a.notes_sewing.size()) o << "# " << a.notes_sewing[k] << "\n";
    o << "[[sewing]]\naction = \"" << (e.action == RigSewing::Add ? "add" : "delete") << "\"\nfrom = " << point_toml(e.from) << "\nto = " << point_toml(e.to)
      << "\n";
  }
  if (!r.swaps.empty() || !r.triggers.empty()) o << "\n# ---- swap sets and triggers, from the shapes' names ----\n";
  for (const RigSwap& s : r.swaps) {
    o << "\n[[swap]]\nname = " << q(s.name) << "\nmembers = [";
    for (size_t k = 0; k < s.members.size(); ++k) o << (k ? ", " : "") << q(s.members[k]);
    o << "]\ndefault = " << q(s.members[size_t(s.default_member)]) << "\n";
  }
  for (const RigTrigger& t : r.triggers) {
    o << "\n[[trigger]]\nname = " << q(t.name) << "\nshapes = [";
    for (size_t k = 0; k < t.shapes.size(); ++k) o << (k ? ", " : "") << q(t.shapes[k]);
    o << "]\n";
  }
  if (!r.physics.empty())
    o << "\n# Secondary motion in a show (docs/motion.md): parts named hair, ear, tail or antenna swing and\n"
         "# settle when what they hang from moves; their handles are the chains' ends (a show's controls\n"
         "# drive them through physics.NAME.mix and .strength). Delete a table to hold a part still.\n";
  for (const RigPhysics& ph : r.physics) {
    o << "[[physics]]\nname = " << q(ph.name) << "\nparts = [";
    for (size_t k = 0; k < ph.parts.size(); ++k) o << (k ? ", " : "") << q(ph.parts[k]);
    o << "]\nfrom = " << q(ph.from) << "\n";
    if (!ph.handle.empty()) o << "handle = " << q(ph.handle) << "\n";
    o << "frequency = " << toml_number(ph.frequency) << "\ndamping = " << toml_number(ph.damping) << "\n\n";
  }
  // The parts with no handle, for the record.
  std::ostringstream rest;
  for (const AutoRigPart& p : a.parts)
    if (p.handle.empty() && p.kind != AutoRigPart::Limb) rest << "#   " << ch.shapes[size_t(p.shape)].id << ": " << p.why << "\n";
  if (!rest.str().empty()) o << "\n# Parts without a handle of their own:\n" << rest.str();
  return o.str();
}

}  // namespace mar
