// The automatic rig from the silhouette (rig/silhouette.h), where the drawing's parts give
// fewer limbs than its silhouette has: a black silhouette under colour pieces, a creature whose
// legs are inside its body's shape, a stick figure of strokes, one flat picture. The rig then
// poses with the topology-aware rigid grid (seed 003), which bends a limb inside one shape: a
// handle at the core and at each limb's free end, and a softer region at each joint and bend,
// so a limb turns there and keeps its shape elsewhere.
#include "rig/auto_rig_silhouette.h"

#include "geom/polygon.h"
#include "rig/limb_geometry.h"
#include "rig/part_names.h"
#include "rig/silhouette.h"

#include <algorithm>
#include <cmath>
#include <set>

namespace mar {

namespace {

// The smallest filled part (by its outline's area) holding `q`; -1 for none.
int smallest_holding(const Character& ch, const std::vector<int>& shapes, const Vec2& q) {
  int best = -1;
  double best_area = 0;
  for (int k : shapes) {
    const SubShape& s = ch.shapes[size_t(k)];
    if (!s.fill.enabled || !s.closed()) continue;
    const Points r = s.largest_ring();
    if (r.size() < 3 || winding_number(r, q) == 0) continue;
    const double a = std::abs(signed_area(r));
    if (best < 0 || a < best_area) {
      best = k;
      best_area = a;
    }
  }
  return best;
}

// Whether a limb of the silhouette turns whole at its joint (a [[bone]]): one and a half of the
// grid's cells wide at least, three times as long as wide and straight (its ends 85 % of its
// length apart; a head: on a neck), and free along its length, the silhouette's outside on both
// sides of its axis at 1.6 half-widths for 70 % of it. An arm drawn down the side of a body in
// one shape, a bust read as a branch of a head, hair lying on a shoulder are not: the grid bends
// them, as it bends every limb without a bone.
bool turns_whole(const SilhouetteLimb& l, const Silhouette& sil, bool head, double cell) {
  if (l.axis.size() < 2 || l.radius.size() != l.axis.size() || sil.outline.size() < 3) return false;
  // (narrower than one and a half of the grid's cells, it has hardly a cell inside it: its outline
  // is its mesh, and its two sides came apart turning whole (a dolphin's tail); the grid bends it)
  if (l.width < 1.5 * cell) return false;
  // (one rigid piece from its joint: long and straight, as an arm, a leg, a neck is; a lock of
  // hair, a wing or a curled tail bends along its length, and the grid bends it)
  const bool necked = head && l.narrowest <= 0.7 * l.end_radius;
  double arc = 0;
  for (size_t k = 1; k < l.axis.size(); ++k) arc += (l.axis[k] - l.axis[k - 1]).norm();
  const bool straight = arc > 0 && (l.axis.back() - l.axis.front()).norm() >= 0.85 * arc;
  if (!necked && (l.length < 3 * l.width || !straight)) return false;
  auto outside = [&](const Vec2& q) {
    if (winding_number(sil.outline, q) == 0) return true;
    for (const Points& h : sil.holes)
      if (h.size() >= 3 && winding_number(h, q) != 0) return true;
    return false;
  };
  size_t free = 0, all = 0;
  for (size_t k = 0; k + 1 < l.axis.size(); ++k) {
    const Vec2 d = l.axis[k + 1] - l.axis[k];
    if (!(d.norm() > 0)) continue;
    const Vec2 across = 1.6 * l.radius[k] * Vec2(-d.y(), d.x()) / d.norm();
    ++all;
    free += outside(l.axis[k] + across) && outside(l.axis[k] - across);
  }
  return all > 0 && double(free) >= 0.7 * double(all);
}

// A limb inside one shape as a [[bone]]: its axis every half-width (1 % of the height at
// least), to a hundredth of a unit.
RigBone bone_of(const SilhouetteLimb& l, const std::string& handle, double height) {
  RigBone b;
  b.handle = handle;
  auto round = [](double v) { return std::round(v * 100) / 100; };
  b.at = Vec2(round(l.joint.x()), round(l.joint.y()));
  double since = INFINITY;
  for (size_t k = 0; k < l.axis.size(); ++k) {
    if (k > 0) since += (l.axis[k] - l.axis[k - 1]).norm();
    const double r = k < l.radius.size() ? l.radius[k] : 0.5 * l.width;
    if (k + 1 < l.axis.size() && since < std::max(0.5 * r, 0.01 * height)) continue;
    b.axis.emplace_back(round(l.axis[k].x()), round(l.axis[k].y()));
    b.radius.push_back(std::max(0.01, round(r)));
    since = 0;
  }
  if (b.axis.size() < 2) b.axis.assign({b.at, b.at + Vec2(0.01, 0)}), b.radius.assign(2, std::max(0.01, round(0.5 * l.width)));
  return b;
}

}  // namespace

bool rig_from_silhouette(const Character& ch, const std::set<int>& members, double height, AutoRig& out,
                         const AutoRigOptions& options) {
  const bool bones = options.bones;
  std::vector<int> drawn;
  for (size_t s = 0; s < ch.shapes.size(); ++s) {
    const SubShape& sh = ch.shapes[s];
    if (members.count(int(s)) || sh.hidden || sh.role != ShapeRole::Paint || (!sh.fill.enabled && !sh.stroke.enabled)) continue;
    bool background = false;
    for (const AutoRigLeftOut& l : out.left_out) background = background || l.shape == int(s);
    if (!background) drawn.push_back(int(s));
  }
  if (drawn.empty()) return false;
  const Silhouette sil = silhouette_of(ch, drawn);
  if (!sil.error.empty() || sil.limbs.empty()) return false;
  // What the parts found: their limbs (and what rides on them: a hand, a claw) and where each
  // ends. A silhouette limb whose free end is on one of them is theirs.
  std::vector<Vec2> part_tips;
  for (const AutoRigPart& p : out.parts)
    if (p.kind == AutoRigPart::Limb && !p.handle.empty())
      for (const RigHandle& h : out.rig.handles)
        if (h.name == p.handle) part_tips.push_back(h.rest);
  std::vector<int> limb_shapes;
  for (const AutoRigPart& p : out.parts) {
    bool on_limb = false;
    for (int q = int(&p - out.parts.data()), guard = 0; q >= 0 && size_t(q) < out.parts.size() && guard < 64; ++guard) {
      on_limb = on_limb || out.parts[size_t(q)].kind == AutoRigPart::Limb;
      q = out.parts[size_t(q)].parent;
    }
    if (on_limb) limb_shapes.push_back(p.shape);
  }
  const double near = 0.03 * height;
  auto on_a_limb = [&](const Vec2& tip) {
    for (const Vec2& t : part_tips)
      if ((t - tip).norm() <= 2 * near) return true;
    for (int k : limb_shapes) {
      const SubShape& sh = ch.shapes[size_t(k)];
      if (sh.fill.enabled && sh.closed()) {
        const Points r = sh.largest_ring();
        if (winding_number(r, tip) != 0 || ring_distance(Points{tip}, r) <= near) return true;
      } else {
        for (size_t i = 0; i + 1 < sh.points.size(); ++i)
          if (point_segment_distance(tip, sh.points[i], sh.points[i + 1]) <= near) return true;
      }
    }
    return false;
  };
  // The grid poses the drawing where its silhouette finds at least two limbs the parts miss;
  // the parts' own limbs ride on it (below), so they lose nothing to it.
  size_t covered = 0;
  for (const SilhouetteLimb& l : sil.limbs) covered += on_a_limb(l.tip);
  const size_t missed = sil.limbs.size() - covered;
  if (missed < 2 && !options.grid_anywhere) return false;

  // Region by region: a limb the parts give with its handle (and a head on its neck) rides on
  // the grid whole, turning about the hinge where it was drawn, with what rides on it; the grid
  // bends only the limbs the silhouette alone finds (a leg inside the body's shape). (A chain's
  // middle, an upper arm with no handle, stays in the grid: riding too, pulled through the
  // hand's handle alone, it left a butterfly 1.26 -> 3.25 % and its reach 3.3 -> 14 %.)
  const std::vector<AutoRigPart> old = out.parts;
  const std::vector<RigHandle> old_handles = out.rig.handles;
  std::vector<char> rides(old.size(), 0);
  for (size_t i = 0; i < old.size(); ++i)
    rides[i] = old[i].has_joint && !old[i].handle.empty() && (old[i].kind == AutoRigPart::Limb || old[i].kind == AutoRigPart::Head);
  auto owner = [&](int i) {  // the first rider up from part i, or -1
    for (int guard = 0; i >= 0 && size_t(i) < old.size() && guard < 64; ++guard, i = old[size_t(i)].parent)
      if (rides[size_t(i)]) return i;
    return -1;
  };
  // A part off the silhouette's region (a head drawn a little above its body, a hat) is in no
  // region of the grid's that a handle reaches: it rides on what it hangs from, hinged at the
  // point of it nearest that part, and turns with the grid there.
  // (one attached to nothing hangs from the part nearest it)
  std::vector<Vec2> hinge_of(old.size());
  std::vector<int> hang(old.size(), -1);
  for (size_t i = 0; i < old.size(); ++i) hinge_of[i] = old[i].joint, hang[i] = old[i].parent;
  std::vector<Points> outline(old.size());
  for (size_t i = 0; i < old.size(); ++i) outline[i] = ch.shapes[size_t(old[i].shape)].largest_ring();
  // the step across the gap between part i and part j, from i's side (32 of i's points): its length
  auto gap = [&](size_t i, size_t j, Vec2* mid) { return ring_gap(outline[i], outline[j], mid); };
  std::vector<Bounds> box(old.size());
  for (size_t i = 0; i < old.size(); ++i)
    for (const Vec2& q : outline[i]) box[i].add(q);
  auto box_gap = [&](size_t i, size_t j) {
    const Vec2 d = (box[j].lo - box[i].hi).cwiseMax(box[i].lo - box[j].hi).cwiseMax(Vec2::Zero());
    return d.norm();
  };
  std::vector<char> scenery(ch.shapes.size(), 0);  // (still where it is drawn: it rides on nothing)
  for (const AutoRigLeftOut& l : out.left_out) scenery[size_t(l.shape)] = 1;
  for (size_t i = 0, floating = 0; i < old.size() && floating < 64; ++i) {  // (at most 64: each is weighed against every part)
    if (rides[i] || old[i].kind == AutoRigPart::Body || owner(int(i)) >= 0 || scenery[size_t(old[i].shape)]) continue;
    if (outline[i].size() < 3 || sil.outline.size() < 3) continue;
    const size_t step = std::max<size_t>(1, outline[i].size() / 64);
    size_t out_of = 0, all = 0;
    for (size_t k = 0; k < outline[i].size(); k += step, ++all) out_of += winding_number(sil.outline, outline[i][k]) == 0;
    if (out_of < 0.85 * double(all)) continue;
    if (hang[i] < 0) {
      double best = INFINITY;
      for (size_t j = 0; j < old.size(); ++j)
        if (j != i && outline[j].size() >= 3 && box_gap(i, j) < best)
          if (const double d = gap(i, j, nullptr); d < best) best = d, hang[i] = int(j);
    }
    if (hang[i] < 0 || outline[size_t(hang[i])].size() < 3) continue;
    gap(i, size_t(hang[i]), &hinge_of[i]);
    rides[i] = 2;
    ++floating;
  }
  // A limb the silhouette alone finds bends in the grid: what holds its free end (a head with
  // its ears in one shape) does not ride, nor what that rides on.
  for (const SilhouetteLimb& l : sil.limbs) {
    if (on_a_limb(l.tip)) continue;
    for (size_t i = 0; i < old.size(); ++i) {
      if (outline[i].size() < 3 || winding_number(outline[i], l.tip) == 0) continue;
      for (int o = owner(int(i)), guard = 0; o >= 0 && guard < 64; o = owner(int(o)), ++guard) rides[size_t(o)] = 0;
    }
  }
  // At most 16 limbs, as a rig from the parts (a head of hair in pieces past the parts' 16 is
  // no limb of the silhouette's either): the silhouette's longest, as many as the parts'
  // limbs leave room for, and none unless two.
  std::vector<size_t> grid_limbs;
  size_t limb_riders = 0;
  for (size_t i = 0; i < old.size(); ++i) limb_riders += old[i].kind == AutoRigPart::Limb;  // (riding or not)
  for (size_t k = 0; k < sil.limbs.size(); ++k)
    if (!on_a_limb(sil.limbs[k].tip)) grid_limbs.push_back(k);
  std::stable_sort(grid_limbs.begin(), grid_limbs.end(), [&](size_t a, size_t b) { return sil.limbs[a].length > sil.limbs[b].length; });
  grid_limbs.resize(std::min(grid_limbs.size(), limb_riders < 16 ? 16 - limb_riders : 0));
  if (grid_limbs.size() < 2 && !options.grid_anywhere) return false;
  std::vector<std::vector<int>> with(old.size());
  std::vector<char> placed(ch.shapes.size(), 0);
  for (const AutoRigPart& p : old) placed[size_t(p.shape)] = 1;
  for (const AutoRigLeftOut& l : out.left_out) placed[size_t(l.shape)] = 1;
  for (size_t i = 0; i < old.size(); ++i)
    if (!rides[i])
      if (const int o = owner(int(i)); o >= 0) with[size_t(o)].push_back(old[i].shape);
  // Shapes no part holds (an outline drawn as a stroke, a swap set's mouths, a small piece past
  // the parts' cap) ride on the rider they lie on: 85 % of their points (32 at most) inside its
  // outline or within 1 % of the height of it.
  const double tol = 0.01 * height;
  auto on_ring = [&](size_t i, const Vec2& q) { return ring_holds(outline[i], q, tol); };
  for (size_t s = 0; s < ch.shapes.size(); ++s) {
    const SubShape& sh = ch.shapes[s];
    if (placed[s] || sh.points.empty()) continue;
    const Bounds b = sh.bounds();
    int best = -1;
    double best_area = 0;
    for (size_t i = 0; i < old.size(); ++i) {
      if (!rides[i] || box[i].empty()) continue;
      const Bounds& r = box[i];
      if (b.lo.x() < r.lo.x() - tol || b.lo.y() < r.lo.y() - tol || b.hi.x() > r.hi.x() + tol || b.hi.y() > r.hi.y() + tol) continue;
      const size_t step = std::max<size_t>(1, sh.points.size() / 32);
      size_t in = 0, all = 0;
      for (size_t k = 0; k < sh.points.size(); k += step, ++all) in += on_ring(i, sh.points[k]);
      const double area = std::abs(signed_area(outline[i]));
      if (in >= 0.85 * double(all) && (best < 0 || area < best_area)) best = int(i), best_area = area;
    }
    if (best >= 0) with[size_t(best)].push_back(int(s));
  }
  auto on_a_rider = [&](const Vec2& tip) {
    for (size_t i = 0; i < old.size(); ++i)
      if (rides[i] && on_ring(i, tip)) return true;
    return false;
  };

  // The rig anew, on the rigid grid; swap sets and triggers stay.
  Rig& rig = out.rig;
  rig.solver = "rigid_grid";
  rig.joints.clear();
  rig.sewing.clear();
  rig.physics.clear();
  rig.handles.clear();
  rig.stiffness.clear();
  rig.riders.clear();
  rig.bones.clear();
  out.notes_sewing.clear();
  out.parts.clear();
  size_t riders = 0;
  for (char r : rides) riders += r != 0;
  if (riders == 0)
    out.notes.push_back("its parts give " + std::to_string(part_tips.size()) + " limb" + (part_tips.size() == 1 ? "" : "s") +
                        " and its silhouette " + std::to_string(sil.limbs.size()) +
                        ": rigged from the silhouette, posed by the rigid grid (a limb bends inside one shape)");
  else
    out.notes.push_back("its parts give " + std::to_string(part_tips.size()) + " limb" + (part_tips.size() == 1 ? "" : "s") +
                        " and its silhouette " + std::to_string(sil.limbs.size()) + ": region by region, " + std::to_string(riders) +
                        " part" + (riders == 1 ? "" : "s") + " ride" + (riders == 1 ? "s" : "") +
                        " whole on the rigid grid, each turning at its joint, and the grid bends the silhouette's other limbs inside their shape");
  std::set<std::string> used;
  auto unique = [&](const std::string& base) { return unique_name(used, base); };
  auto name_at = [&](int shape, const std::string& fallback) {
    if (shape < 0) return fallback;
    const SubShape& s = ch.shapes[size_t(shape)];
    const bool named = !s.label.empty() || !made_up(s.id);
    const std::string base = named ? handle_name(s.label.empty() ? s.id : s.label) : "";
    return base.empty() ? fallback : base;
  };
  const Bounds cb = ch.bounds();  // (the grid's cell, as the rig leaves it: the diagonal / 40)
  const double cell = cb.empty() ? 0.0 : (cb.hi - cb.lo).norm() / 40;
  const int core_shape = smallest_holding(ch, drawn, sil.core);
  AutoRigPart body;
  body.shape = core_shape >= 0 ? core_shape : drawn.front();
  body.kind = AutoRigPart::Body;
  body.why = "the body: the widest part of the silhouette";
  body.handle = unique("body");
  rig.handles.push_back({body.handle, sil.core});
  out.parts.push_back(body);
  // Scenery stays where it is drawn, out of the grid's mesh: in it, a rectangle under the whole
  // drawing (a bunny cut out of a green square) joined every limb to every other through it, and
  // one handle held it no better than a pin, so it turned and sheared with them.
  for (const AutoRigLeftOut& l : out.left_out) {
    RigRider d;
    d.part = ch.shapes[size_t(l.shape)].id;
    d.still = true;
    if (std::none_of(rig.riders.begin(), rig.riders.end(), [&](const RigRider& o) { return o.part == d.part; })) rig.riders.push_back(d);
  }
  // The head: a limb wide at its end (half again as wide as its neck, and a third of the body),
  // the widest such, above the core; or the one whose end a part named head holds.
  std::vector<int> holder(sil.limbs.size());  // the part holding each limb's free end
  for (size_t k = 0; k < sil.limbs.size(); ++k) holder[k] = smallest_holding(ch, drawn, sil.limbs[k].tip);
  int head = -1;
  for (size_t k = 0; k < sil.limbs.size(); ++k) {
    const SilhouetteLimb& l = sil.limbs[k];
    const int at = holder[k];
    const bool named = at >= 0 && hint_of(name_words(ch.shapes[size_t(at)].label.empty() ? ch.shapes[size_t(at)].id : ch.shapes[size_t(at)].label)) == Hint::Head;
    const bool wide = l.end_radius >= 1.5 * l.narrowest && l.end_radius >= 0.35 * sil.core_radius && l.tip.y() < sil.core.y();
    if (named || (wide && (head < 0 || l.end_radius > sil.limbs[size_t(head)].end_radius))) head = int(k);
    if (named) break;
  }
  for (size_t k = 0; k < sil.limbs.size(); ++k) {
    const SilhouetteLimb& l = sil.limbs[k];
    if (on_a_rider(l.tip)) continue;  // a part's limb: it rides (below)
    if (std::find(grid_limbs.begin(), grid_limbs.end(), k) == grid_limbs.end() && !on_a_limb(l.tip)) continue;  // (past 16)
    AutoRigPart p;
    const int at = holder[k];
    p.shape = at >= 0 ? at : body.shape;
    p.parent = 0;
    p.kind = int(k) == head ? AutoRigPart::Head : AutoRigPart::Limb;
    p.has_joint = true;
    p.joint = l.joint;
    p.path = l.axis;
    p.path_radius = l.radius;
    const std::string side = l.tip.x() < sil.core.x() ? "left" : "right";
    p.handle = unique(int(k) == head ? name_at(at, "head") : name_at(at == body.shape ? -1 : at, "limb-" + side));
    p.why = int(k) == head ? "a head: a branch of the silhouette wide at its end, turning at its neck"
                           : "a limb: a branch of the silhouette, jointed where it narrows";
    rig.handles.push_back({p.handle, int(k) == head ? l.end_centre : l.tip});  // (a head: at its middle)
    // softer where it joins and where it bends: it turns there
    rig.stiffness.push_back({p.handle + "-joint", l.joint, std::max(0.6 * l.width, 0.01 * height), 0.25, 0});
    for (size_t b = 0; b < l.bends.size(); ++b)
      rig.stiffness.push_back({p.handle + "-bend", l.bends[b], std::max(0.6 * l.width, 0.01 * height), 0.35, 0});
    if (bones && turns_whole(l, sil, int(k) == head, cell)) rig.bones.push_back(bone_of(l, p.handle, height));
    out.parts.push_back(p);
  }
  if (!rig.bones.empty())
    out.notes.push_back(std::to_string(rig.bones.size()) + " of its limbs inside one shape turn" + (rig.bones.size() == 1 ? "s" : "") +
                        " whole at " + (rig.bones.size() == 1 ? "its joint" : "their joints") + " (--bones: long, straight and free of the rest)");
  else if (bones)
    out.notes.push_back("no limb inside one shape is long, straight and free enough to turn whole (--bones): the grid bends them");
  // The riders, parents first (a forearm on its upper arm), each with its own handle.
  std::vector<int> now(old.size(), -1);  // old part -> new part
  for (size_t pass = 0; pass < old.size(); ++pass)
    for (size_t i = 0; i < old.size(); ++i) {
      if (!rides[i] || now[i] >= 0) continue;
      const int up = hang[i] >= 0 ? owner(hang[i]) : -1;
      if (up >= 0 && now[size_t(up)] < 0) continue;  // its parent first
      AutoRigPart p = old[i];
      p.parent = up >= 0 ? now[size_t(up)] : 0;
      p.has_joint = true;
      p.joint = hinge_of[i];
      RigRider d;
      d.part = ch.shapes[size_t(p.shape)].id;
      d.on = up >= 0 ? ch.shapes[size_t(old[size_t(up)].shape)].id : hang[i] >= 0 ? ch.shapes[size_t(old[size_t(hang[i])].shape)].id : "";
      d.at = p.joint;
      if (rides[i] == 2) p.handle.clear();  // (off the region: it follows what it hangs from)
      for (const RigHandle& h : old_handles)
        if (!p.handle.empty() && h.name == p.handle) {
          p.handle = unique(h.name);
          rig.handles.push_back({p.handle, h.rest});
          d.handle = p.handle;
        }
      for (int k : with[i]) d.with.push_back(ch.shapes[size_t(k)].id);
      rig.riders.push_back(std::move(d));
      now[i] = int(out.parts.size());
      out.parts.push_back(p);
    }
  return true;
}

}  // namespace mar
