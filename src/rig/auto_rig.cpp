#include "rig/auto_rig.h"

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

struct Geo {
  int shape = -1;
  Points ring;  ///< the outer outline (the largest closed contour)
  double area = 0;
  Vec2 lo{0, 0}, hi{0, 0};
  Vec2 centroid{0, 0};
  std::vector<std::string> words;
  bool named = false;
  Hint hint = Hint::None;
};

}  // namespace

AutoRig auto_rig(const Character& ch, const std::string& character, const std::string& mask, const AutoRigOptions& options) {
  AutoRig out;
  Rig& rig = out.rig;
  rig.character = character;
  rig.mask = mask;
  const Bounds cb = ch.bounds();
  const double height = cb.empty() ? 1.0 : std::max(1e-9, cb.hi.y() - cb.lo.y());

  // ---- swap sets and triggers from names and groups (part_names.cpp) -------------------------
  const std::set<int> members = swaps_and_triggers(ch, rig);  // shown and hidden: not parts of the tree

  // ---- the parts: closed, filled sub-shapes ---------------------------------------------------
  std::vector<Geo> geo;
  int traced_pieces = 0;
  for (size_t s = 0; s < ch.shapes.size(); ++s) {
    const SubShape& sh = ch.shapes[s];
    if (members.count(int(s)) || sh.role != ShapeRole::Paint) continue;  // (a clip or mask shape rides along)
    Geo g;
    g.shape = int(s);
    g.ring = sh.largest_ring();
    g.area = std::abs(signed_area(g.ring));
    // A shape drawn in pieces (an outline as many small filled quads, a limb in strips): its
    // outline is the outline of all its pieces together.
    // (at most 64 such shapes, each a twentieth of the drawing's height or more: each is drawn
    // and traced, and a file of thousands of tiny ones took 18 s)
    // (the `rig` command's only: a show's plain rig loads without drawing and tracing)
    if (options.silhouette && sh.contours.size() > 3 && sh.fill.enabled && traced_pieces < 64) {
      const Bounds b = sh.bounds();
      const double box = b.empty() ? 0.0 : (b.hi.x() - b.lo.x()) * (b.hi.y() - b.lo.y());
      if (g.area < 0.3 * box && std::max(b.hi.x() - b.lo.x(), b.hi.y() - b.lo.y()) >= 0.05 * height && ++traced_pieces)
        if (Points u = union_outline(sh); u.size() >= 3 && std::abs(signed_area(u)) > g.area) {
          g.ring = std::move(u);
          g.area = std::abs(signed_area(g.ring));
        }
    }
    if (!sh.fill.enabled || g.area <= 1e-6 * height * height) continue;
    g.lo = g.hi = g.ring[0];
    for (const Vec2& p : g.ring) {
      g.lo = g.lo.cwiseMin(p);
      g.hi = g.hi.cwiseMax(p);
    }
    g.centroid = ring_centroid(g.ring);
    g.named = !sh.label.empty() || !made_up(sh.id);
    if (g.named) g.words = name_words(sh.label.empty() ? sh.id : sh.label);
    g.hint = hint_of(g.words);
    geo.push_back(std::move(g));
  }
  const size_t n = geo.size();
  if (n == 0) {
    if (!options.silhouette || !rig_from_silhouette(ch, members, height, out))
      out.notes.push_back("no filled part to rig, and no limb in its silhouette");
    return out;
  }

  // ---- overlaps --------------------------------------------------------------------------------
  std::vector<std::vector<double>> overlap(n, std::vector<double>(n, 0.0));
  std::vector<std::vector<Vec2>> overlap_at(n, std::vector<Vec2>(n, Vec2::Zero()));
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j) {
      if (geo[i].hi.x() < geo[j].lo.x() || geo[j].hi.x() < geo[i].lo.x() || geo[i].hi.y() < geo[j].lo.y() || geo[j].hi.y() < geo[i].lo.y())
        continue;
      Vec2 c;
      double a = 0;
      if (overlap_centre(geo[i].ring, geo[j].ring, c, &a) && a > 0) {
        overlap[i][j] = overlap[j][i] = a;
        overlap_at[i][j] = overlap_at[j][i] = c;
      }
    }
  // Scenery: a disc or a rectangle behind most of the character (a sun, a frame), or a shadow
  // under its feet. Left out of the tree, never the body; a handle keeps it where it is drawn.
  std::vector<char> scenery(n, 0);
  {
    // (again after each find: a second disc inside a glow behind a horse)
    for (bool found = true; found;) {
    found = false;
    double total = 0;
    for (size_t i = 0; i < n; ++i) total += scenery[i] ? 0.0 : geo[i].area;
    for (size_t i = 0; i < n && n >= 3; ++i) {
      if (geo[i].hint != Hint::None || scenery[i]) continue;  // (a part named as one is one)
      const double others = total - geo[i].area;
      double inside = 0, behind = 0;
      bool straddled = false;  // a big part of the character half in front of it, half beside it
      for (size_t j = 0; j < n; ++j) {
        if (j == i || scenery[j]) continue;
        const double in = std::min(overlap[i][j], geo[j].area);
        inside += in;
        if (geo[j].shape > geo[i].shape) behind += geo[j].area;
        straddled = straddled || (geo[j].shape > geo[i].shape && geo[j].area >= 0.25 * geo[i].area && in >= 0.2 * geo[j].area &&
                                  in <= 0.8 * geo[j].area);
      }
      const Vec2 ext = geo[i].hi - geo[i].lo;
      const double box = std::max(1e-12, ext.x() * ext.y());
      const bool plain = geo[i].area >= 0.7 * box;  // a disc (0.785 of its box), a rectangle
      const bool first = behind >= 0.7 * others;    // drawn behind the rest
      // (a body drawn first has its limbs attached along its outline; a backdrop has the
      // character itself crossing it)
      // (and a rectangle under the whole drawing is its background, whatever is on it)
      const Vec2 all = cb.hi - cb.lo;
      const bool canvas = geo[i].area >= 0.95 * box && first && box >= 0.9 * all.x() * all.y();
      const bool backdrop = (plain && first && geo[i].area >= 0.3 * others && straddled) || canvas;
      const bool ground = plain && first && ext.x() >= 3 * ext.y() && geo[i].centroid.y() >= cb.lo.y() + 0.8 * height &&
                          geo[i].area <= 0.3 * others && inside > 0;
      if (!backdrop && !ground) continue;
      scenery[i] = 1;
      found = true;
      out.left_out.push_back({geo[i].shape, canvas     ? "a rectangle under the whole drawing, its background: kept still, never the body"
                                            : backdrop ? "a disc or rectangle behind most of the character: kept still, never the body"
                                                       : "a shadow under the feet: kept still"});
    }
    }
  }
  // Details: mostly inside a bigger part (eyes, a pocket, spots). They follow their container.
  // An outline and its fill drawn as two shapes, one right after the other (a black shape a
  // little larger behind the colour, or the colour over it) are twins: the one drawn later
  // rides on the first, so the pair is one part.
  std::vector<int> container(n, -1);
  for (size_t i = 0; i < n; ++i) {
    if (scenery[i]) continue;
    for (size_t j = 0; j < n && container[i] < 0; ++j) {
      if (j == i || scenery[j] || geo[j].shape >= geo[i].shape || geo[i].shape - geo[j].shape > 2) continue;
      const double lo = std::min(geo[i].area, geo[j].area), hi = std::max(geo[i].area, geo[j].area);
      if (lo >= 0.5 * hi && overlap[i][j] >= 0.7 * lo) container[i] = int(j);
    }
  }
  for (size_t i = 0; i < n; ++i) {
    double best = 0;
    if (scenery[i] || container[i] >= 0) continue;
    for (size_t j = 0; j < n; ++j)
      if (j != i && !scenery[j] && geo[j].area > geo[i].area && overlap[i][j] >= 0.85 * geo[i].area && overlap[i][j] > best) {
        best = overlap[i][j];
        container[i] = int(j);
      }
  }
  // Neighbours among the others: overlapping, or within 2% of the height of each other.
  std::vector<std::vector<int>> nb(n);
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j) {
      if (container[i] >= 0 || container[j] >= 0 || scenery[i] || scenery[j]) continue;
      bool near = overlap[i][j] > 0;
      if (!near) {
        const double gap = 0.02 * height;
        const bool boxes = !(geo[i].hi.x() + gap < geo[j].lo.x() || geo[j].hi.x() + gap < geo[i].lo.x() || geo[i].hi.y() + gap < geo[j].lo.y() ||
                             geo[j].hi.y() + gap < geo[i].lo.y());
        if (boxes && ring_distance(geo[i].ring, geo[j].ring) <= gap) {
          near = true;
          // where they come closest stands for the overlap
          double best = std::numeric_limits<double>::infinity();
          for (const Vec2& p : geo[i].ring)
            for (size_t k = 0; k < geo[j].ring.size(); ++k) {
              const double d = point_segment_distance(p, geo[j].ring[k], geo[j].ring[(k + 1) % geo[j].ring.size()]);
              if (d < best) {
                best = d;
                overlap_at[i][j] = overlap_at[j][i] = p;
              }
            }
        }
      }
      if (near) {
        nb[i].push_back(int(j));
        nb[j].push_back(int(i));
      }
    }
  // The part at a point: inside it or within 2% of the height of it, the smallest holding it;
  // parts mostly inside another only `with_details`.
  std::vector<char> is_part(ch.shapes.size(), 0);
  for (const Geo& g : geo) is_part[size_t(g.shape)] = 1;
  auto part_at = [&](const Vec2& q, bool with_details) {
    int best = -1;
    double bd = 0.02 * height;
    for (size_t i = 0; i < n; ++i) {
      if ((!with_details && container[i] >= 0) || scenery[i]) continue;
      const double d = winding_number(geo[i].ring, q) != 0 ? 0.0 : ring_distance(Points{q}, geo[i].ring);
      if (d <= bd && (best < 0 || d < bd || geo[i].area < geo[size_t(best)].area)) {
        bd = d;
        best = int(i);
      }
    }
    return best;
  };
  // Connectors: an open stroke from one part to another (a wick from a candle to its flame)
  // joins them; a hinge then goes where it leaves the parent.
  std::vector<std::vector<int>> via(n, std::vector<int>(n, -1));           // the stroke's shape
  std::vector<std::vector<Vec2>> stroke_end(n, std::vector<Vec2>(n, Vec2::Zero()));  // its end at the first part
  {
    for (size_t s = 0; s < ch.shapes.size(); ++s) {
      const SubShape& sh = ch.shapes[s];
      if (is_part[s] || members.count(int(s)) || !sh.stroke.enabled) continue;
      for (const Contour& c : sh.contours) {
        if (c.closed || c.count < 2) continue;
        const Vec2 a = sh.points[size_t(c.begin)], b = sh.points[size_t(c.begin + c.count - 1)];
        const int pa = part_at(a, false), pb = part_at(b, false);
        if (pa < 0 || pb < 0 || pa == pb || overlap[size_t(pa)][size_t(pb)] > 0) continue;
        if (std::find(nb[size_t(pa)].begin(), nb[size_t(pa)].end(), pb) != nb[size_t(pa)].end()) continue;
        nb[size_t(pa)].push_back(pb);
        nb[size_t(pb)].push_back(pa);
        via[size_t(pa)][size_t(pb)] = via[size_t(pb)][size_t(pa)] = int(s);
        stroke_end[size_t(pa)][size_t(pb)] = a;
        stroke_end[size_t(pb)][size_t(pa)] = b;
        overlap_at[size_t(pa)][size_t(pb)] = a;  // (where each is attached: its end of the stroke)
        overlap_at[size_t(pb)][size_t(pa)] = b;
      }
    }
  }
  auto hops_from = [&](size_t root) {
    std::vector<int> d(n, -1);
    std::deque<int> q{int(root)};
    d[root] = 0;
    while (!q.empty()) {
      const int u = q.front();
      q.pop_front();
      for (int v : nb[size_t(u)])
        if (d[size_t(v)] < 0) {
          d[size_t(v)] = d[size_t(u)] + 1;
          q.push_back(v);
        }
    }
    return d;
  };
  // ---- the body: the part the others hang from ------------------------------------------------
  // Most area within reach, then least area-weighted distance to it (a torso, not a wing or
  // a face). A part named body or torso wins among those that reach as much.
  size_t root = 0;
  double best_reach = -1, best_cost = 0;
  bool best_named = false;
  for (size_t r = 0; r < n; ++r) {
    if (container[r] >= 0 || scenery[r]) continue;
    const auto d = hops_from(r);
    double reach = 0, cost = 0;
    for (size_t p = 0; p < n; ++p)
      if (d[p] >= 0) {
        reach += geo[p].area;
        cost += geo[p].area * d[p];
      }
    const bool named = geo[r].hint == Hint::Body;
    const bool better = reach > best_reach * 1.0001 ||
                        (reach >= best_reach * 0.9999 && (named != best_named ? named : cost < best_cost));
    if (better) {
      root = r;
      best_reach = reach;
      best_cost = cost;
      best_named = named;
    }
  }
  // ---- the tree ----------------------------------------------------------------------------------
  // Out from the body through overlaps (and connectors) first, nearest overlapping parent; a
  // part only near its neighbours (drawn touching) joins where nothing overlapping reaches it.
  // A forearm that overlaps its upper arm and only touches the torso hangs from the arm.
  std::vector<int> parent(n, -1), depth(n, -1);
  {
    auto overlapping = [&](size_t i, size_t j) { return overlap[i][j] > 0 || via[i][j] >= 0; };
    depth[root] = 0;
    std::deque<size_t> q{root};
    for (;;) {
      while (!q.empty()) {
        const size_t u = q.front();
        q.pop_front();
        for (int v : nb[u])
          if (depth[size_t(v)] < 0 && overlapping(u, size_t(v))) {
            depth[size_t(v)] = depth[u] + 1;
            parent[size_t(v)] = int(u);
            q.push_back(size_t(v));
          } else if (depth[size_t(v)] == depth[u] + 1 && overlapping(u, size_t(v)) && parent[size_t(v)] >= 0 &&
                     overlap[size_t(v)][u] > overlap[size_t(v)][size_t(parent[size_t(v)])]) {
            parent[size_t(v)] = int(u);  // of two parents as near the body, the one it overlaps most
          }
      }
      // The nearest unreached part touching a reached one.
      size_t best_v = n, best_u = n;
      for (size_t v = 0; v < n; ++v) {
        if (depth[v] >= 0 || container[v] >= 0) continue;
        for (int u : nb[v])
          if (depth[size_t(u)] >= 0 && (best_v == n || depth[size_t(u)] < depth[best_u])) {
            best_v = v;
            best_u = size_t(u);
          }
      }
      if (best_v == n) break;
      depth[best_v] = depth[best_u] + 1;
      parent[best_v] = int(best_u);
      q.push_back(best_v);
    }
    for (size_t i = 0; i < n; ++i)
      if (container[i] >= 0) parent[i] = container[i];
  }
  // ---- kinds ----------------------------------------------------------------------------------------
  out.parts.resize(n);
  std::vector<Axis> axes(n);
  std::vector<char> flap(n, 0);  // a limb by its name, not by its shape: attached along a side
  for (size_t i = 0; i < n; ++i) {
    AutoRigPart& p = out.parts[i];
    p.shape = geo[i].shape;
    p.parent = parent[i];
    axes[i] = principal_axis(geo[i].ring);
    if (i == root) {
      p.kind = AutoRigPart::Body;
      p.why = "the body: the part the others hang from";
      continue;
    }
    if (scenery[i]) {
      p.why = "scenery, left out of the character: kept still";
      continue;
    }
    if (container[i] >= 0) {
      const Geo& c = geo[size_t(container[i])];
      const bool twin = c.shape < geo[i].shape && geo[i].area >= 0.5 * c.area && c.area >= 0.5 * geo[i].area;
      p.why = (twin ? "the outline or fill of " : "mostly inside ") + ch.shapes[size_t(c.shape)].id +
              (twin ? ", drawn apart: one part with it" : ": follows it");
      continue;
    }
    if (parent[i] < 0) {
      p.why = "attached to nothing: sewn to the part nearest it";
      continue;
    }
    const size_t par = size_t(parent[i]);
    const Axis& ax = axes[i];
    const Vec2 at = overlap_at[i][par];
    const double along = (at - ax.centre).dot(ax.major);
    const bool elongated = ax.half_major >= 1.4 * ax.half_minor;
    const bool at_end = std::abs(along) > 0.45 * ax.half_major;
    const Hint h = geo[i].hint;
    // (a part named as a limb only needs to hang off-centre: a fan of a tail, a round ear)
    const bool off_centre = (at - geo[i].centroid).norm() > 0.5 * std::sqrt(geo[i].area / M_PI);
    if ((elongated && at_end) || ((h == Hint::Limb || h == Hint::Hand) && off_centre)) {
      p.kind = AutoRigPart::Limb;
      p.why = std::string("a limb on ") + ch.shapes[size_t(geo[par].shape)].id +
              (elongated && at_end ? ", attached at one end" : ", by its name");
      flap[i] = !(elongated && at_end);
    } else if (h == Hint::Head || geo[i].area >= 0.15 * geo[root].area) {
      p.kind = AutoRigPart::Head;
      p.why = h == Hint::Head ? "a head, by its name" : "a big part that is not a limb";
    } else {
      p.why = "a detail on " + ch.shapes[size_t(geo[par].shape)].id + ": follows it";
    }
  }
  // A part hung along its side (an upper arm beside a torso) with a limb at one end of its long
  // axis is that limb's first link, attached at its other end.
  std::vector<char> end_attached(n, 0);
  std::vector<Vec2> attach_at(n, Vec2::Zero());
  for (size_t i = 0; i < n; ++i) {
    const Axis& ax = axes[i];
    const bool candidate = out.parts[i].kind == AutoRigPart::Detail || (out.parts[i].kind == AutoRigPart::Head && geo[i].hint != Hint::Head);
    if (!candidate || container[i] >= 0 || parent[i] < 0 || ax.half_major < 1.4 * ax.half_minor) continue;
    // (beside its parent, not at one end of it: a dish a candle stands on is not an arm)
    const Axis& pax = axes[size_t(parent[i])];
    if (std::abs((overlap_at[i][size_t(parent[i])] - pax.centre).dot(pax.major)) > 0.45 * pax.half_major) continue;
    for (size_t c = 0; c < n; ++c) {
      if (parent[c] != int(i) || out.parts[c].kind != AutoRigPart::Limb) continue;
      const double along = (overlap_at[c][i] - ax.centre).dot(ax.major);
      if (std::abs(along) <= 0.45 * ax.half_major) continue;
      out.parts[i].kind = AutoRigPart::Limb;
      out.parts[i].why = "a limb on " + ch.shapes[size_t(geo[size_t(parent[i])].shape)].id + ", hung along its side, its next link at its other end";
      end_attached[i] = 1;
      attach_at[i] = ax.centre - (along > 0 ? 1.0 : -1.0) * ax.half_major * ax.major;
      break;
    }
  }
  // One head: the parts named head or face, else the biggest candidate (hair on a head, a
  // hat, a second big part are details of what they sit on).
  {
    bool named_head = false;
    size_t biggest = n;
    for (size_t i = 0; i < n; ++i)
      if (out.parts[i].kind == AutoRigPart::Head) {
        named_head = named_head || geo[i].hint == Hint::Head;
        if (biggest == n || geo[i].area > geo[biggest].area) biggest = i;
      }
    for (size_t i = 0; i < n; ++i)
      if (out.parts[i].kind == AutoRigPart::Head && (named_head ? geo[i].hint != Hint::Head : i != biggest)) {
        out.parts[i].kind = AutoRigPart::Detail;
        out.parts[i].why = "a detail on " + ch.shapes[size_t(geo[size_t(parent[i])].shape)].id + ": follows it";
      }
  }
  // Hands and feet on a limb's end are limbs too (the chain goes on), whatever their shape.
  for (size_t i = 0; i < n; ++i)
    if (out.parts[i].kind == AutoRigPart::Detail && geo[i].hint == Hint::Hand && parent[i] >= 0 && container[i] < 0 &&
        out.parts[size_t(parent[i])].kind == AutoRigPart::Limb) {
      out.parts[i].kind = AutoRigPart::Limb;
      out.parts[i].why = "a " + geo[i].words.front() + " at the end of " + ch.shapes[size_t(geo[size_t(parent[i])].shape)].id;
    }

  // A detail that overlaps a limb hanging from its parent more than it overlaps the parent (a
  // sleeve on a shoulder, a cuff) goes with the limb.
  for (size_t i = 0; i < n; ++i) {
    if (out.parts[i].kind != AutoRigPart::Detail || container[i] >= 0 || parent[i] < 0) continue;
    const int q = parent[i];
    int best = -1;
    for (size_t l = 0; l < n; ++l)
      if (l != i && parent[l] == q && out.parts[l].kind == AutoRigPart::Limb && overlap[i][l] > overlap[i][size_t(q)] &&
          (best < 0 || overlap[i][l] > overlap[i][size_t(best)]))
        best = int(l);
    if (best >= 0) {
      parent[i] = best;
      out.parts[i].parent = best;
      out.parts[i].why = "a detail on " + ch.shapes[size_t(geo[size_t(best)].shape)].id + ", which it overlaps most: follows it";
    }
  }

  // At most 16 limbs, the biggest: a head of hair or a beard in two hundred small filled pieces
  // is not two hundred limbs to a performer; the smaller ride on what they hang from.
  {
    std::vector<std::pair<double, size_t>> limbs;
    for (size_t i = 0; i < n; ++i)
      if (out.parts[i].kind == AutoRigPart::Limb) limbs.push_back({-geo[i].area, i});
    std::stable_sort(limbs.begin(), limbs.end());
    for (size_t k = 16; k < limbs.size(); ++k) {
      AutoRigPart& p = out.parts[limbs[k].second];
      p.kind = AutoRigPart::Detail;
      p.why = "a small limb among many: rides on " + ch.shapes[size_t(geo[size_t(parent[limbs[k].second])].shape)].id;
    }
  }

  // ---- hinges at the drawn joints ------------------------------------------------------------------
  for (size_t i = 0; i < n; ++i) {
    AutoRigPart& p = out.parts[i];
    if (options.head_hinge && p.kind == AutoRigPart::Head && parent[i] >= 0 && container[i] < 0) {
      // A head hanging from the body turns about its neck: where it meets what it hangs from.
      const size_t par = size_t(parent[i]);
      p.has_joint = true;
      p.joint = via[i][par] >= 0 ? stroke_end[par][i] : overlap_at[i][par];
      p.why += ", turning about its neck";
      RigJoint j;
      j.has_at = true;
      j.at = p.joint;
      j.part_a = ch.shapes[size_t(p.shape)].id;
      j.part_b = ch.shapes[size_t(geo[par].shape)].id;
      if (const int s = via[i][par]; s >= 0) j.part_a = ch.shapes[size_t(s)].id;
      rig.joints.push_back(j);
      continue;
    }
    if (p.kind != AutoRigPart::Limb) continue;
    const size_t par = size_t(parent[i]);
    // Walking its medial axis in from the free end, the joint is at the attached end's centre,
    // or where the axis goes into the parent.
    const Vec2 attached = end_attached[i] ? attach_at[i] : overlap_at[i][par];
    p.path = medial_path(geo[i].ring, attached);

    const auto& path = p.path;
    p.joint = path.empty() ? attached : path.back();
    // A wing, a fan of a tail, a fin: it turns about the middle of where it meets the parent.
    if (flap[i]) p.joint = attached;
    if (!path.empty() && !flap[i]) {
      auto radius = [&](const Vec2& q) {
        double r = std::numeric_limits<double>::infinity();
        for (size_t k = 0; k < geo[i].ring.size(); ++k)
          r = std::min(r, point_segment_distance(q, geo[i].ring[k], geo[i].ring[(k + 1) % geo[i].ring.size()]));
        return r;
      };
      // The centre of the attached end: back from the end along the axis by the limb's half
      // width there (the centre of the circle that rounds a round end off, of the square that
      // ends a flat one), the half width being the typical distance to the outline near the end.
      std::vector<double> rs;
      for (size_t k = path.size() * 6 / 10; k < path.size() * 9 / 10; ++k) rs.push_back(radius(path[k]));
      double half_width = 0;
      if (!rs.empty()) {
        std::nth_element(rs.begin(), rs.begin() + long(rs.size() / 2), rs.end());
        half_width = rs[rs.size() / 2];
      }
      Vec2 cap = path.back();
      double run = 0;
      for (size_t k = path.size() - 1; k > 0 && run < half_width; --k) {
        const double step = (path[k] - path[k - 1]).norm();
        if (run + step >= half_width) {
          cap = path[k] + (path[k - 1] - path[k]) * ((half_width - run) / std::max(1e-12, step));
          break;
        }
        run += step;
        cap = path[k - 1];
      }
      // Where the axis goes into the parent's outline, walking in from the free end.
      size_t entry_k = path.size();
      Vec2 entry = path.back();
      for (size_t k = 0; k < path.size(); ++k) {
        if (winding_number(geo[par].ring, path[k]) == 0) continue;
        entry_k = k;
        entry = path[k];
        if (k > 0) {
          const Points step{path[k - 1], path[k]};
          double best = std::numeric_limits<double>::infinity();
          for (const Vec2& x : crossings(step, geo[par].ring))
            if ((x - path[k - 1]).norm() < best) {
              best = (x - path[k - 1]).norm();
              entry = x;
            }
        }
        break;
      }
      // A limb drawn over its parent shows its end: the joint is the end's centre. One drawn
      // under it turns where it goes in, unless the parent hides only a short piece of it (a
      // shoulder behind a torso, a thigh's top under shorts): at most three half widths and
      // 40% of its length.
      double hidden = 0;
      for (size_t k = entry_k; k + 1 < path.size(); ++k) hidden += (path[k + 1] - path[k]).norm();
      const bool over = geo[i].shape > geo[par].shape;
      const bool cap_inside = winding_number(geo[par].ring, cap) != 0;
      double total = 0;
      for (size_t k = 0; k + 1 < path.size(); ++k) total += (path[k + 1] - path[k]).norm();
      const bool long_stub = entry_k < path.size() && hidden > 3 * radius(cap) && hidden > 0.4 * total;
      // (a cap outside the parent: a flap attached along a side, a wing, turns where it meets it)
      // (an upper arm hung beside its torso turns at the centre of its top, inside or not)
      p.joint = (end_attached[i] || (cap_inside && (over || !long_stub))) ? cap : entry;
    }
    p.has_joint = true;
    RigJoint j;
    j.has_at = true;
    j.at = p.joint;
    j.part_a = ch.shapes[size_t(p.shape)].id;
    j.part_b = ch.shapes[size_t(geo[par].shape)].id;
    if (const int s = via[i][par]; s >= 0) {
      // Through a connector: the stroke turns where it leaves the parent (the limb is welded
      // to its other end, as crossings are).
      p.joint = j.at = stroke_end[par][i];
      j.part_a = ch.shapes[size_t(s)].id;
    }
    rig.joints.push_back(j);
  }

  // ---- sewing that follows the tree --------------------------------------------------------------------
  // The solver sews each part to its nearest neighbour (a spanning tree over the parts). Where
  // that is not its parent or child here — a forearm touching the torso's side — the line would
  // hold a limb to a part it does not hang from: it is deleted, and a part left with no tie to
  // its parent (no hinge, no line) is sewn to it at their closest points.
  {
    // (the spanning tree alone: no joints, so no welds are made of its crossing lines)
    Character refined = ch;
    FrameOptions fo = frame_options_from_rig(rig);
    fo.auto_joints = false;
    fo.joints.clear();
    refine_for_frame(refined, fo);
    const FeatureFrame f = build_feature_frame(refined, fo);
    std::vector<int> part_of(ch.shapes.size(), -1);
    for (size_t i = 0; i < n; ++i) part_of[size_t(geo[i].shape)] = int(i);
    // (a part attached to nothing keeps the line that ties it to its nearest: without it, it
    // would float free and stay wherever a pull left it)
    auto loose = [&](int i) { return parent[size_t(i)] < 0 && size_t(i) != root && !scenery[size_t(i)]; };
    auto related = [&](int i, int j) { return parent[size_t(i)] == j || parent[size_t(j)] == i || loose(i) || loose(j); };
    std::vector<char> tied(n, 0);
    for (const RigJoint& j : rig.joints)
      for (size_t i = 0; i < n; ++i)
        if (ch.shapes[size_t(geo[i].shape)].id == j.part_a || (via[i][size_t(std::max(0, parent[i]))] >= 0 && parent[i] >= 0)) tied[i] = 1;
    // The spanning tree's lines: the sewing lines right after the feature lines, one per
    // sub-frame but the first (welds made of its crossing lines come after them).
    size_t subframes = 0;
    for (const auto& sub : f.subframes) subframes += !sub.empty();
    const size_t first = size_t(f.feature_lines), last = std::min(f.lines.size(), first + (subframes > 0 ? subframes - 1 : 0));
    for (size_t li = first; li < last; ++li) {
      const FrameLine& l = f.lines[li];
      if (l.kind != FrameLine::Sewing) break;
      const int sa = f.origin[size_t(l.a)].shape, sb = f.origin[size_t(l.b)].shape;
      if (sa == sb || size_t(sa) >= part_of.size() || size_t(sb) >= part_of.size()) continue;
      const int i = part_of[size_t(sa)], j = part_of[size_t(sb)];
      if (i < 0 || j < 0) continue;
      if (related(i, j)) {
        tied[size_t(parent[size_t(i)] == j ? i : j)] = 1;
        continue;
      }
      RigSewing del;
      del.action = RigSewing::Delete;
      del.from = f.rest[size_t(l.a)];
      del.to = f.rest[size_t(l.b)];
      rig.sewing.push_back(del);
      out.notes_sewing.push_back(ch.shapes[size_t(sa)].id + " and " + ch.shapes[size_t(sb)].id + " touch but neither hangs from the other: not sewn");
    }
    for (size_t i = 0; i < n; ++i) {
      if (tied[i] || parent[i] < 0 || rig.sewing.empty()) continue;
      // The closest frame vertices of the part and its parent; then a second pair, away from
      // the first, so the part cannot turn about it: with one line, a pen that dragged it round
      // left it there (the hardware show's neck on the shirt). (`away_from`: no point of the
      // part within `apart` of it.)
      const int ps = geo[i].shape, qs = geo[size_t(parent[i])].shape;
      auto closest = [&](const Vec2& away_from, double apart, RigSewing& line) {
        double best = std::numeric_limits<double>::infinity();
        line.action = RigSewing::Add;
        for (size_t a = 0; a < f.rest.size(); ++a) {
          if (f.origin[a].shape != ps || (f.rest[a] - away_from).norm() < apart) continue;
          for (size_t b = 0; b < f.rest.size(); ++b)
            if (f.origin[b].shape == qs && (f.rest[a] - f.rest[b]).norm() < best) {
              best = (f.rest[a] - f.rest[b]).norm();
              line.from = f.rest[a];
              line.to = f.rest[b];
            }
        }
        return std::isfinite(best);
      };
      RigSewing nearest, other;
      if (!closest(Vec2::Zero(), 0, nearest)) continue;
      const std::string names = ch.shapes[size_t(ps)].id + " sewn to " + ch.shapes[size_t(qs)].id;
      rig.sewing.push_back(nearest);
      out.notes_sewing.push_back(names + ", which it hangs from");
      if (closest(nearest.from, 0.5 * std::max(axes[i].half_major, axes[i].half_minor), other)) {
        rig.sewing.push_back(other);
        out.notes_sewing.push_back(names + " a second time, away from the first: it keeps its turn");
      }
    }
  }

  // ---- handles -----------------------------------------------------------------------------------------
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
  // Strokes that hang from a part by one end (whiskers, antennae, a curl): limbs too, hinged
  // where they leave the part, a handle at the free end. (A stroke with both ends on parts is a
  // connector or a line drawn on them: a mouth, a belt.)
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
  // Where the silhouette has limbs the parts do not give: rigged from it (auto_rig_silhouette.cpp).
  if (options.silhouette && rig_from_silhouette(ch, members, height, out)) return out;
  add_named_chains(ch, out);  // hair, ears, tails, antennae swing in a show (part_names.cpp)
  if (n == 1) out.notes.push_back("one part only: the rig has a body handle; draw limbs as parts of their own (or PNG layers) for hinges");
  return out;
}

int add_drawn_joints(const Character& ch, Rig& rig) {
  // (the parts' limbs only, as a plain rig has always had them: its head hangs as sewn)
  const AutoRig ar = auto_rig(ch, rig.character, rig.mask, AutoRigOptions{false, false});
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
