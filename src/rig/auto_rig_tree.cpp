// The automatic rig's tree (rig/auto_rig_graph.h): the body, the parts hanging from it, and
// what each part is (a limb, the head, a detail that follows its parent).
#include "rig/auto_rig_graph.h"

#include <algorithm>
#include <cmath>
#include <deque>

namespace mar {

void grow_tree(PartGraph& G, AutoRig& out) {
  const Character& ch = G.ch;
  const std::vector<PartGeo>& geo = G.geo;
  const size_t n = G.n;
  const auto& overlap = G.overlap;
  const auto& overlap_at = G.overlap_at;
  const auto& scenery = G.scenery;
  const auto& container = G.container;
  const auto& nb = G.nb;
  const auto& via = G.via;
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
  size_t& root = G.root;
  root = 0;
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
  auto& parent = G.parent;
  parent.assign(n, -1);
  std::vector<int> depth(n, -1);
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
  auto& axes = G.axes;
  axes.assign(n, Axis{});
  auto& flap = G.flap;
  flap.assign(n, 0);  // a limb by its name, not by its shape: attached along a side
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
      const PartGeo& c = geo[size_t(container[i])];
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
  auto& end_attached = G.end_attached;
  auto& attach_at = G.attach_at;
  end_attached.assign(n, 0);
  attach_at.assign(n, Vec2::Zero());
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
}

}  // namespace mar
