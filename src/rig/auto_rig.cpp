#include "rig/auto_rig.h"
#include "rig/auto_rig_graph.h"

#include "rig/auto_rig_silhouette.h"

#include "frame/feature_frame.h"
#include "frame/joints.h"
#include "geom/polygon.h"
#include "rig/limb_geometry.h"
#include "rig/part_names.h"
#include "rig/silhouette.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <set>

namespace mar {

namespace {

// A handle on the body, on scenery (driven by nothing: it holds it still), on the head and at
// the free end of each limb chain; returns the names used.
std::set<std::string> place_handles(const PartGraph& G, AutoRig& out) {
  const Character& ch = G.ch;
  Rig& rig = out.rig;
  const std::vector<PartGeo>& geo = G.geo;
  const size_t n = G.n;
  const size_t root = G.root;
  const auto& scenery = G.scenery;
  const auto& parent = G.parent;
  std::set<std::string> used;
  auto unique = [&](const std::string& base) { return unique_name(used, base); };
  const Vec2 body_centre = geo[root].centroid;
  auto add_handle = [&](size_t i, const std::string& fallback, const Vec2& at) {
    const SubShape& sh = ch.shapes[size_t(geo[i].shape)];
    const std::string base = geo[i].named ? handle_name(sh.label.empty() ? sh.id : sh.label) : fallback;
    out.parts[i].handle = unique(base.empty() ? fallback : base);
    rig.handles.push_back({out.parts[i].handle, at});
  };
  add_handle(root, "body", geo[root].centroid);
  for (size_t i = 0; i < n; ++i)
    if (scenery[i]) add_handle(i, "scenery", geo[i].centroid);  // (driven by nothing: it holds it still)
  for (size_t i = 0; i < n; ++i)
    if (out.parts[i].kind == AutoRigPart::Head) add_handle(i, "head", geo[i].centroid);
  for (size_t i = 0; i < n; ++i) {
    if (out.parts[i].kind != AutoRigPart::Limb) continue;
    bool has_limb_child = false;
    for (size_t c = 0; c < n; ++c)
      has_limb_child = has_limb_child || (parent[c] == int(i) && (out.parts[c].kind == AutoRigPart::Limb || out.parts[c].kind == AutoRigPart::Head));
    if (has_limb_child) continue;  // the chain's last part (or the head on a neck) carries the handle
    // On the medial axis, 8% of the way in from the free end (inside a rounded tip).
    const auto& path = out.parts[i].path;
    Vec2 tip = out.parts[i].joint;
    if (!path.empty()) {
      double total = 0;
      for (size_t k = 1; k < path.size(); ++k) total += (path[k] - path[k - 1]).norm();
      tip = path[0];
      double run = 0;
      for (size_t k = 1; k < path.size() && run < 0.08 * total; ++k) {
        run += (path[k] - path[k - 1]).norm();
        tip = path[k];
      }
    }
    const std::string side = tip.x() < body_centre.x() ? "left" : "right";
    add_handle(i, "limb-" + side, tip);
  }
  return used;
}

// Strokes that hang from a part by one end (whiskers, antennae, a curl): limbs too, hinged
// where they leave the part, a handle at the free end. (A stroke with both ends on parts is a
// connector or a line drawn on them: a mouth, a belt.)
void hang_strands(const PartGraph& G, AutoRig& out, std::set<std::string>& used) {
  const Character& ch = G.ch;
  Rig& rig = out.rig;
  const double height = G.height;
  const std::vector<PartGeo>& geo = G.geo;
  const size_t n = G.n;
  const auto& via = G.via;
  const auto& is_part = G.is_part;
  const std::set<int>& members = G.members;
  const Vec2 body_centre = geo[G.root].centroid;
  auto part_at = [&](const Vec2& q, bool with_details) { return G.part_at(q, with_details); };
  auto unique = [&](const std::string& base) { return unique_name(used, base); };
  {
    std::vector<char> connector(ch.shapes.size(), 0);
    for (size_t i = 0; i < n; ++i)
      for (size_t j = 0; j < n; ++j)
        if (via[i][j] >= 0) connector[size_t(via[i][j])] = 1;
    // (the eight longest: a head of hair drawn in two hundred strokes is a head of hair, not
    // two hundred handles; the others ride on what they hang from)
    auto strand = [&](size_t s) {
      const SubShape& sh = ch.shapes[s];
      if (is_part[s] || connector[s] || members.count(int(s)) || !sh.stroke.enabled || sh.contours.size() != 1) return -1.0;
      const Contour& c = sh.contours[0];
      if (c.closed || c.count < 2) return -1.0;
      double length = 0;
      for (int k = 1; k < c.count; ++k) length += (sh.points[size_t(c.begin + k)] - sh.points[size_t(c.begin + k - 1)]).norm();
      if (length < 0.04 * height) return -1.0;
      const int pa = part_at(sh.points[size_t(c.begin)], true), pb = part_at(sh.points[size_t(c.begin + c.count - 1)], true);
      return (pa >= 0) == (pb >= 0) ? -1.0 : length;
    };
    std::vector<std::pair<double, size_t>> strands;
    for (size_t s = 0; s < ch.shapes.size(); ++s)
      if (const double len = strand(s); len > 0) strands.push_back({-len, s});
    std::stable_sort(strands.begin(), strands.end());
    std::set<size_t> longest;
    for (size_t k = 0; k < strands.size() && k < 8; ++k) longest.insert(strands[k].second);
    for (size_t s = 0; s < ch.shapes.size(); ++s) {
      if (!longest.count(s)) continue;
      const SubShape& sh = ch.shapes[s];
      const Contour& c = sh.contours[0];
      const std::span<const Vec2> pts(sh.points.data() + c.begin, size_t(c.count));
      const double length = strand(s);
      const int pa = part_at(pts.front(), true), pb = part_at(pts.back(), true);
      const bool from_front = pa >= 0;
      const int par = from_front ? pa : pb;
      // the free end, 8% of the way back along the stroke
      Vec2 tip = from_front ? pts.back() : pts.front();
      double run = 0;
      for (size_t k = 1; k < pts.size() && run < 0.08 * length; ++k) {
        const size_t a = from_front ? pts.size() - k : k - 1, b = from_front ? pts.size() - k - 1 : k;
        run += (pts[b] - pts[a]).norm();
        tip = pts[b];
      }
      AutoRigPart p;
      p.shape = int(s);
      p.parent = par;
      p.kind = AutoRigPart::Limb;
      p.has_joint = true;
      p.joint = from_front ? pts.front() : pts.back();
      p.why = "a stroke hanging from " + ch.shapes[size_t(geo[size_t(par)].shape)].id + " by one end";
      RigJoint j;
      j.has_at = true;
      j.at = p.joint;
      j.part_a = sh.id;
      j.part_b = ch.shapes[size_t(geo[size_t(par)].shape)].id;
      rig.joints.push_back(j);
      const bool named = !sh.label.empty() || !made_up(sh.id);
      const std::string base = named ? handle_name(sh.label.empty() ? sh.id : sh.label) : std::string("strand-") + (tip.x() < body_centre.x() ? "left" : "right");
      p.handle = unique(base);
      rig.handles.push_back({p.handle, tip});
      out.parts.push_back(p);
    }
  }
}

// Each detail on a part rides on it whole: out of the frame, carried by its part's motion
// about where it is on it. (Not one a limb or the head hangs from: their hinges are in the
// frame.)
void ride_details(const PartGraph& G, AutoRig& out) {
  const Character& ch = G.ch;
  std::vector<char> holds(G.n, 0);
  for (size_t i = 0; i < G.n; ++i)
    if (out.parts[i].kind != AutoRigPart::Detail)
      for (int q = G.parent[i], guard = 0; q >= 0 && guard < 64; q = G.parent[size_t(q)], ++guard) holds[size_t(q)] = 1;
  for (size_t i = 0; i < G.n; ++i)  // (a strand hangs from it: a hair curl on a cap)
    for (const RigJoint& j : out.rig.joints) holds[i] = holds[i] || j.part_a == G.id(i) || j.part_b == G.id(i);
  std::vector<char> rides(G.n, 0);
  for (size_t i = 0; i < G.n; ++i) {
    const AutoRigPart& p = out.parts[i];
    if (p.kind != AutoRigPart::Detail || G.parent[i] < 0 || G.scenery[i] || holds[i] || G.geo[i].ring.size() < 3) continue;
    // (a fill drawn inside its own outline, as big as it, bends with it in the frame, sewn to it
    // twice (sew_tree): carried rigidly, its bending outline showed wedges past it)
    if (const int c = G.container[i]; c >= 0 && G.geo[i].area >= 0.5 * G.geo[size_t(c)].area) continue;
    // (two pieces each mostly inside the other: the second stays in the frame, or each would carry the other)
    bool loop = false;
    for (int q = G.parent[i], guard = 0; q >= 0 && guard < 4096; q = G.parent[size_t(q)], ++guard) {
      if (q == int(i)) loop = true;
      if (loop || !rides[size_t(q)]) break;
    }
    if (loop) continue;
    rides[i] = 1;
    RigRider d;
    d.part = ch.shapes[size_t(p.shape)].id;
    d.on = ch.shapes[size_t(G.geo[size_t(G.parent[i])].shape)].id;
    d.at = G.geo[i].centroid;
    out.rig.riders.push_back(std::move(d));
  }
  // A part attached to nothing (a pictogram's head drawn apart from its shoulders), with no
  // handle and nothing hanging from it, rides on the nearest part that hangs in the tree, about
  // the middle of the gap between them. Held in the frame by one sewing line, it could turn and
  // grow about that line's end: a woman's head swelled to eight times the drawing's height.
  auto loose = [&](size_t i) { return G.parent[i] < 0 && i != G.root && !G.scenery[i]; };
  for (size_t i = 0; i < G.n; ++i) {
    if (!loose(i) || rides[i] || holds[i] || !out.parts[i].handle.empty() || G.geo[i].ring.size() < 3) continue;
    double best = INFINITY;
    int on = -1;
    Vec2 at = G.geo[i].centroid;
    for (size_t j = 0; j < G.n; ++j) {
      if (j == i || loose(j) || G.scenery[j] || rides[j] || G.geo[j].ring.size() < 3) continue;
      const Vec2 apart = (G.geo[j].lo - G.geo[i].hi).cwiseMax(G.geo[i].lo - G.geo[j].hi).cwiseMax(Vec2::Zero());
      if (apart.norm() >= best) continue;  // (its box is further than the nearest found)
      Vec2 mid;
      if (const double d = ring_gap(G.geo[i].ring, G.geo[j].ring, &mid); d < best) best = d, on = int(j), at = mid;
    }
    if (on < 0) continue;
    rides[i] = 1;
    out.parts[i].why = "attached to nothing: rides whole on " + G.id(size_t(on)) + ", the part nearest it";
    RigRider d;
    d.part = G.id(i);
    d.on = G.id(size_t(on));
    d.at = at;
    out.rig.riders.push_back(std::move(d));
  }
  // A shape that is no part (an outline drawn as a stroke of its own, the crease of a sleeve,
  // a small piece past the parts' cap) rides on the smallest part that holds it: 85 % of its
  // points (32 at most) inside that part's outline or within 1 % of the height of it, as the
  // grid's riders carry theirs. Left in the frame, it hung on one sewing line and lagged its part.
  std::vector<char> taken(ch.shapes.size(), 0);
  for (const AutoRigPart& p : out.parts)
    if (p.shape >= 0) taken[size_t(p.shape)] = 1;
  for (const auto& row : G.via)
    for (int v : row)
      if (v >= 0) taken[size_t(v)] = 1;
  for (int m : G.members) taken[size_t(m)] = 1;
  for (const AutoRigLeftOut& l : out.left_out) taken[size_t(l.shape)] = 1;
  std::set<std::string> jointed;
  for (const RigJoint& j : out.rig.joints) jointed.insert(j.part_a), jointed.insert(j.part_b);
  const double tol = 0.01 * G.height;
  for (size_t s = 0; s < ch.shapes.size() && out.rig.riders.size() < 4096; ++s) {
    const SubShape& sh = ch.shapes[s];
    if (taken[s] || G.is_part[s] || sh.id.empty() || sh.hidden || sh.role != ShapeRole::Paint || sh.points.empty() || jointed.count(sh.id)) continue;
    if (!sh.fill.enabled && !sh.stroke.enabled) continue;
    const Bounds b = sh.bounds();
    // the smallest part holding 85 % of it; else the part holding most of it, half at least (a
    // cat's whiskers, half on its muzzle: in the frame they were sewn to whatever was nearest
    // once the muzzle rode, and a head tilt bent them)
    int best = -1, most = -1;
    double most_share = 0;
    const size_t step = std::max<size_t>(1, sh.points.size() / 32);
    for (size_t i = 0; i < G.n; ++i) {
      if (G.scenery[i] || G.geo[i].ring.size() < 3) continue;
      const PartGeo& g = G.geo[i];
      if (b.hi.x() < g.lo.x() - tol || b.hi.y() < g.lo.y() - tol || b.lo.x() > g.hi.x() + tol || b.lo.y() > g.hi.y() + tol) continue;
      size_t in = 0, all = 0;
      for (size_t k = 0; k < sh.points.size(); k += step, ++all) in += ring_holds(g.ring, sh.points[k], tol);
      const double share = double(in) / double(std::max<size_t>(1, all));
      if (share >= 0.85 && (best < 0 || g.area < G.geo[size_t(best)].area)) best = int(i);
      if (share >= 0.5 && (most < 0 || share > most_share || (share == most_share && g.area < G.geo[size_t(most)].area))) most_share = share, most = int(i);
    }
    if (best < 0) best = most;
    if (best < 0) continue;
    RigRider d;
    d.part = sh.id;
    d.on = G.id(size_t(best));
    Vec2 c = Vec2::Zero();
    for (const Vec2& q : sh.points) c += q;
    d.at = c / double(sh.points.size());
    out.rig.riders.push_back(std::move(d));
  }
}

}  // namespace

AutoRig auto_rig(const Character& ch, const std::string& character, const std::string& mask, const AutoRigOptions& options) {
  AutoRig out;
  Rig& rig = out.rig;
  rig.character = character;
  rig.mask = mask;
  const Bounds cb = ch.bounds();
  const double height = cb.empty() ? 1.0 : std::max(1e-9, cb.hi.y() - cb.lo.y());
  PartGraph G(ch, height);

  // ---- swap sets and triggers from names and groups (part_names.cpp) -------------------------
  G.members = swaps_and_triggers(ch, rig);  // shown and hidden: not parts of the tree
  const std::set<int>& members = G.members;

  // ---- the parts: closed, filled sub-shapes, how they overlap and touch (auto_rig_parts.cpp) ----
  find_parts(G, options);
  const size_t n = G.n;
  if (n == 0) {
    if (!options.silhouette || !rig_from_silhouette(ch, members, height, out, options))
      out.notes.push_back("no filled part to rig, and no limb in its silhouette");
    return out;
  }
  relate_parts(G, out);
  // ---- the body, the tree and each part's kind (auto_rig_tree.cpp) -----------------------------
  grow_tree(G, out);
  // ---- hinges at the drawn joints (auto_rig_joints.cpp) ----------------------------------------------
  place_hinges(G, out, options);

  // ---- handles, and strokes hanging by one end as strands ------------------------------------------
  std::set<std::string> used = place_handles(G, out);
  hang_strands(G, out, used);
  // ---- details riding on their parts; sewing that follows the tree (auto_rig_joints.cpp) ----------
  if (options.ride_details) ride_details(G, out);
  sew_tree(G, out);
  // Where the silhouette has limbs the parts do not give: rigged from it (auto_rig_silhouette.cpp).
  if (options.silhouette && rig_from_silhouette(ch, members, height, out, options)) return out;
  add_named_chains(ch, out);  // hair, ears, tails, antennae swing in a show (part_names.cpp)
  if (options.bones && n > 1)
    out.notes.push_back("--bones has nothing to do: its limbs are parts of their own, which turn whole at their hinges already");
  if (n == 1) out.notes.push_back("one part only: the rig has a body handle; draw limbs as parts of their own (or PNG layers) for hinges");
  return out;
}

int add_drawn_joints(const Character& ch, Rig& rig) {
  // (the parts' limbs only, as a plain rig has always had them: its head hangs as sewn)
  AutoRigOptions plain;
  plain.silhouette = false;
  plain.head_hinge = false;
  plain.ride_details = false;  // (the hand-written rig's frame holds its details)
  const AutoRig ar = auto_rig(ch, rig.character, rig.mask, plain);
  const Bounds b = ch.bounds();
  const double near = 0.02 * (b.empty() ? 1.0 : std::max(1e-9, b.hi.y() - b.lo.y()));
  auto shape_of = [&](const std::string& id) {
    for (size_t s = 0; s < ch.shapes.size(); ++s)
      if (ch.shapes[s].id == id) return int(s);
    return -1;
  };
  int added = 0;
  const size_t stated = rig.joints.size();
  for (const RigJoint& j : ar.rig.joints) {
    // (a stroke hanging by one end, a whisker, stays as the solver has it)
    // (nor does a head's neck: a plain rig's head hangs as its sewing holds it)
    bool stroke_limb = false;
    for (const AutoRigPart& p : ar.parts)
      stroke_limb = stroke_limb || (p.kind == AutoRigPart::Limb && p.shape == shape_of(j.part_a) && !ch.shapes[size_t(p.shape)].fill.enabled) ||
                    (p.kind == AutoRigPart::Head && p.shape == shape_of(j.part_a));
    if (stroke_limb) continue;
    bool taken = false;
    for (size_t k = 0; k < stated; ++k) {
      const RigJoint& r = rig.joints[k];
      const bool pair = (r.part_a == j.part_a && r.part_b == j.part_b) || (r.part_a == j.part_b && r.part_b == j.part_a);
      taken = taken || pair || (r.has_at && (r.at - j.at).norm() <= near);
    }
    if (taken) continue;
    rig.joints.push_back(j);
    ++added;
  }
  // (the rig's own sewing first; an edit it already has, as `marionette rig` wrote it, is not
  // made twice: a second delete would take the next nearest line)
  const size_t own = rig.sewing.size();
  for (const RigSewing& e : ar.rig.sewing) {
    bool have = false;
    for (size_t k = 0; k < own; ++k) {
      const RigSewing& r = rig.sewing[k];
      have = have || (r.action == e.action && (r.from - e.from).norm() < 0.2 && (r.to - e.to).norm() < 0.2);
    }
    if (!have) rig.sewing.push_back(e);
  }
  return added;
}

}  // namespace mar
