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

}  // namespace

bool rig_from_silhouette(const Character& ch, const std::set<int>& members, double height, AutoRig& out) {
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
  size_t covered = 0;
  for (const SilhouetteLimb& l : sil.limbs) covered += on_a_limb(l.tip);
  // (region by region would be finer: here the silhouette takes over where it finds at least
  // two limbs the parts miss, and at least as many as the parts found)
  const size_t missed = sil.limbs.size() - covered;
  if (missed < std::max<size_t>(2, part_tips.size())) return false;

  // The rig anew, on the rigid grid; swap sets and triggers stay.
  Rig& rig = out.rig;
  rig.solver = "rigid_grid";
  rig.joints.clear();
  rig.sewing.clear();
  rig.physics.clear();
  rig.handles.clear();
  rig.stiffness.clear();
  out.notes_sewing.clear();
  out.parts.clear();
  out.notes.push_back("its parts give " + std::to_string(part_tips.size()) + " limb" + (part_tips.size() == 1 ? "" : "s") +
                      " and its silhouette " + std::to_string(sil.limbs.size()) +
                      ": rigged from the silhouette, posed by the rigid grid (a limb bends inside one shape)");
  std::set<std::string> used;
  auto unique = [&](const std::string& base) { return unique_name(used, base); };
  auto name_at = [&](int shape, const std::string& fallback) {
    if (shape < 0) return fallback;
    const SubShape& s = ch.shapes[size_t(shape)];
    const bool named = !s.label.empty() || !made_up(s.id);
    const std::string base = named ? handle_name(s.label.empty() ? s.id : s.label) : "";
    return base.empty() ? fallback : base;
  };
  const int core_shape = smallest_holding(ch, drawn, sil.core);
  AutoRigPart body;
  body.shape = core_shape >= 0 ? core_shape : drawn.front();
  body.kind = AutoRigPart::Body;
  body.why = "the body: the widest part of the silhouette";
  body.handle = unique("body");
  rig.handles.push_back({body.handle, sil.core});
  out.parts.push_back(body);
  for (const AutoRigLeftOut& l : out.left_out) {  // scenery: a handle driven by nothing holds it
    const Points r = ch.shapes[size_t(l.shape)].largest_ring();
    if (r.size() >= 3) rig.handles.push_back({unique("scenery"), ring_centroid(r)});
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
    AutoRigPart p;
    const int at = holder[k];
    p.shape = at >= 0 ? at : body.shape;
    p.parent = 0;
    p.kind = int(k) == head ? AutoRigPart::Head : AutoRigPart::Limb;
    p.has_joint = true;
    p.joint = l.joint;
    p.path = l.axis;
    const std::string side = l.tip.x() < sil.core.x() ? "left" : "right";
    p.handle = unique(int(k) == head ? name_at(at, "head") : name_at(at == body.shape ? -1 : at, "limb-" + side));
    p.why = int(k) == head ? "a head: a branch of the silhouette wide at its end, turning at its neck"
                           : "a limb: a branch of the silhouette, jointed where it narrows";
    rig.handles.push_back({p.handle, int(k) == head ? l.end_centre : l.tip});  // (a head: at its middle)
    // softer where it joins and where it bends: it turns there
    rig.stiffness.push_back({p.handle + "-joint", l.joint, std::max(0.6 * l.width, 0.01 * height), 0.25, 0});
    for (size_t b = 0; b < l.bends.size(); ++b)
      rig.stiffness.push_back({p.handle + "-bend", l.bends[b], std::max(0.6 * l.width, 0.01 * height), 0.35, 0});
    out.parts.push_back(p);
  }
  return true;
}

}  // namespace mar
