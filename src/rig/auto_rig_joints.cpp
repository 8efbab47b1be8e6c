// The automatic rig's joints (rig/auto_rig_graph.h): a hinge where each limb goes into what it
// hangs from (and the head at its neck), and sewing that follows the tree.
#include "rig/auto_rig_graph.h"

#include "frame/feature_frame.h"
#include "geom/polygon.h"
#include "rig/limb_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mar {

void place_hinges(const PartGraph& G, AutoRig& out, const AutoRigOptions& options) {
  const Character& ch = G.ch;
  Rig& rig = out.rig;
  const std::vector<PartGeo>& geo = G.geo;
  const size_t n = G.n;
  const auto& overlap_at = G.overlap_at;
  const auto& container = G.container;
  const auto& via = G.via;
  const auto& stroke_end = G.stroke_end;
  const auto& parent = G.parent;
  const auto& flap = G.flap;
  const auto& end_attached = G.end_attached;
  const auto& attach_at = G.attach_at;
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
  // A group drawn as one part (join_groups): each other piece is welded to the piece that
  // stands for it: a weld holds their turn as well as their place. (Sewn instead, a piece
  // that crossed the part the group hangs from was hinged to it there and held back while the
  // rest of the group turned: on 24 held-out drawings, 71 % came back to rest against 83 %.)
  for (size_t i = 0; i < n; ++i) {
    const int rep = G.group_part[i];
    if (rep < 0 || size_t(rep) == i || G.scenery[i] || container[i] != rep) continue;
    RigJoint weld;
    weld.weld = true;
    weld.has_at = true;
    weld.at = overlap_at[i][size_t(rep)];
    weld.part_a = G.id(i);
    weld.part_b = G.id(size_t(rep));
    rig.joints.push_back(weld);
  }
}

void sew_tree(const PartGraph& G, AutoRig& out) {
  const Character& ch = G.ch;
  Rig& rig = out.rig;
  const std::vector<PartGeo>& geo = G.geo;
  const size_t n = G.n;
  const size_t root = G.root;
  const auto& scenery = G.scenery;
  const auto& via = G.via;
  const auto& parent = G.parent;
  const auto& axes = G.axes;
  // The solver sews each part to its nearest neighbour (a spanning tree over the parts). Where
  // that is not its parent or child here — a forearm touching the torso's side — the line would
  // hold a limb to a part it does not hang from: it is deleted, and a part left with no tie to
  // its parent (no hinge, no line) is sewn to it at their closest points.
  {
    // (the spanning tree alone: no joints, so no welds are made of its crossing lines)
    // (the frame as the solver builds it: a detail that rides is out of it)
    Character refined = ch;
    std::vector<char> rides(ch.shapes.size(), 0);
    for (const RigRider& d : rig.riders)
      for (size_t s = 0; s < ch.shapes.size(); ++s)
        if (ch.shapes[s].id == d.part) {
          rides[s] = 1;
          refined.shapes[s].points.clear();
          refined.shapes[s].contours.clear();
        }
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
    // An outline and its fill drawn as two shapes (one inside the other, at least half its
    // area): one part. Tied to it by the spanning tree's one line and no hinge, the fill would
    // turn about that line, half out of its outline: where that line meets it, per part.
    auto twin = [&](size_t i) {
      const int c = G.container[i];
      return c >= 0 && c == parent[i] && geo[i].area >= 0.5 * geo[size_t(c)].area && geo[size_t(c)].area >= 0.5 * geo[i].area;
    };
    // A detail that limbs hang from (shorts on a shirt, the legs hinged on them), tied to its
    // parent by that one line too: a kicking leg turned it about the line, pulling the shorts
    // off the body.
    auto holds_limbs = [&](size_t i) {
      if (out.parts[i].kind != AutoRigPart::Detail) return false;
      for (const RigJoint& j : rig.joints)
        if (!j.weld && j.part_b == ch.shapes[size_t(geo[i].shape)].id) return true;
      return false;
    };
    std::vector<Vec2> one_line(n, Vec2::Zero());
    std::vector<char> by_one_line(n, 0);
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
        const size_t child = size_t(parent[size_t(i)] == j ? i : j);
        if (!tied[child] && parent[child] >= 0 && (twin(child) || holds_limbs(child))) {
          by_one_line[child] = 1;
          one_line[child] = f.rest[size_t(child == size_t(i) ? l.a : l.b)];
        }
        tied[child] = 1;
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
      if ((tied[i] && !by_one_line[i]) || parent[i] < 0 || (rig.sewing.empty() && !by_one_line[i]) || rides[size_t(geo[i].shape)]) continue;
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
      const std::string names = ch.shapes[size_t(ps)].id + " sewn to " + ch.shapes[size_t(qs)].id;
      if (by_one_line[i]) {
        nearest.from = one_line[i];  // (the solver's own line is the first)
      } else {
        if (!closest(Vec2::Zero(), 0, nearest)) continue;
        rig.sewing.push_back(nearest);
        out.notes_sewing.push_back(names + ", which it hangs from");
      }
      if (closest(nearest.from, 0.5 * std::max(axes[i].half_major, axes[i].half_minor), other)) {
        rig.sewing.push_back(other);
        out.notes_sewing.push_back(names + " a second time, away from the first: it keeps its turn");
      }
    }
  }
}

}  // namespace mar
