// Riders on the rigid grid (solve/rigid_grid.h): parts out of the mesh that turn whole about a
// hinge the grid (or another rider) carries. Read from the rig and linked at prepare; placed
// after each solve, with no allocation.
#include "solve/rigid_grid.h"

#include "geom/polygon.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace mar {

bool RigidGrid::prepare_riders(const Character& ch, const Rig& rig, std::string* error) {
  auto at = [&](const RigRider& d) { return rig.path + ":" + std::to_string(d.line) + ": rider '" + d.part + "'"; };
  std::unordered_map<std::string, int> index;  // (once: a rider's `with` may name dozens of shapes)
  for (size_t k = ch.shapes.size(); k-- > 0;) index[ch.shapes[k].id] = int(k);  // (the first of a repeated id)
  auto shape_of = [&](const std::string& id) {
    const auto it = index.find(id);
    return it == index.end() ? -1 : it->second;
  };
  std::vector<int> part(rig.riders.size()), on(rig.riders.size(), -1);
  for (size_t r = 0; r < rig.riders.size(); ++r) {
    const RigRider& d = rig.riders[r];
    part[r] = shape_of(d.part);
    if (part[r] < 0) {
      if (error) *error = at(d) + " is not a sub-shape of the character (inspect lists them)";
      return false;
    }
  }
  for (size_t r = 0; r < rig.riders.size(); ++r) {
    const RigRider& d = rig.riders[r];
    if (d.on.empty()) continue;
    if (shape_of(d.on) < 0) {
      if (error) *error = at(d) + " hangs on '" + d.on + "', which is not a sub-shape of the character";
      return false;
    }
    for (size_t q = 0; q < rig.riders.size(); ++q)
      if (rig.riders[q].part == d.on) on[r] = int(q);
  }
  // Parents first; a rider hanging (through others) on itself is refused.
  std::vector<int> order, placed(rig.riders.size(), -1);
  while (order.size() < rig.riders.size()) {
    const size_t before = order.size();
    for (size_t r = 0; r < rig.riders.size(); ++r)
      if (placed[r] < 0 && (on[r] < 0 || placed[size_t(on[r])] >= 0)) {
        placed[r] = int(order.size());
        order.push_back(int(r));
      }
    if (order.size() == before) {
      for (size_t r = 0; r < rig.riders.size(); ++r)
        if (placed[r] < 0) {
          if (error) *error = at(rig.riders[r]) + " hangs, through riders, on itself";
          return false;
        }
    }
  }
  const int first = int(riders_.size());  // (after the bones)
  for (int r : order) {
    const RigRider& d = rig.riders[size_t(r)];
    Rider x;
    x.parent = on[size_t(r)] >= 0 ? first + placed[size_t(on[size_t(r)])] : -1;
    x.hinge = d.at;
    x.t = d.at;
    x.handle = d.handle.empty() ? -1 : rig.find_handle(d.handle);
    x.still = d.still;
    x.ring = ch.shapes[size_t(part[size_t(r)])].largest_ring();
    for (const Vec2& q : ch.shapes[size_t(part[size_t(r)])].points) x.reach = std::max(x.reach, (q - x.hinge).norm());
    std::vector<int> shapes{part[size_t(r)]};
    for (const std::string& id : d.with) {
      const int k = shape_of(id);
      if (k < 0) {
        if (error) *error = at(d) + ": '" + id + "' (with) is not a sub-shape of the character";
        return false;
      }
      shapes.push_back(k);
    }
    for (int k : shapes) {
      if (rider_of_[size_t(k)] >= 0) {
        if (error) *error = at(d) + ": '" + ch.shapes[size_t(k)].id + "' rides on two riders";
        return false;
      }
      rider_of_[size_t(k)] = int(riders_.size());
    }
    x.shapes = std::move(shapes);
    riders_.push_back(std::move(x));
  }
  return true;
}

// The bones, first among the riders (a rider hinged on a bone's limb hangs on it).
void RigidGrid::prepare_bones(const Rig& rig) {
  for (const RigBone& b : rig.bones) {
    Rider x;
    x.bone = true;
    x.hinge = x.t = b.at;
    x.handle = b.handle.empty() ? -1 : rig.find_handle(b.handle);
    x.axis = b.axis;
    x.radius = b.radius;
    x.radius.resize(x.axis.size(), x.radius.empty() ? 1.0 : x.radius.back());
    x.band = b.band > 0 ? b.band : x.radius.back();
    for (size_t k = 0; k < x.axis.size(); ++k) x.reach = std::max(x.reach, (x.axis[k] - x.hinge).norm() + x.radius[k]);
    riders_.push_back(std::move(x));
  }
}

namespace {

// Where a rest point is against a bone's axis: u, its signed distance along the limb from the
// joint (< 0 on the limb's side: the arc length to the joint from its nearest axis point, or
// beside the joint its step along the axis's last direction), and ρ, its distance from the axis
// in the limb's half-widths there.
struct AxisPlace {
  double u = 0, rho = INFINITY;
};
AxisPlace axis_place(const Points& A, const std::vector<double>& R, const Vec2& joint, const Vec2& q) {
  AxisPlace best;
  double s = 0, s_best = 0, total = 0;
  bool at_joint = false;
  for (size_t j = 1; j < A.size(); ++j) total += (A[j] - A[j - 1]).norm();
  for (size_t j = 1; j < A.size(); ++j) {
    const Vec2 ab = A[j] - A[j - 1];
    const double len = ab.norm(), t = len > 0 ? std::clamp((q - A[j - 1]).dot(ab) / (len * len), 0.0, 1.0) : 0.0;
    const double r = std::max(1e-12, (1 - t) * R[j - 1] + t * R[j]);
    if (const double rho = (q - (A[j - 1] + t * ab)).norm() / r; rho < best.rho) {
      best.rho = rho;
      s_best = s + t * len;
      at_joint = j + 1 == A.size() && t >= 1;
    }
    s += len;
  }
  const Vec2 last = A.back() - A[A.size() - 2];
  best.u = at_joint && last.norm() > 0 ? (q - joint).dot(last.normalized()) : s_best - total;
  return best;
}

// How much of a bone's turn a point there takes: along the limb none at the joint and all of it
// past 2·band; across it all within 1.5 half-widths of the axis, fading to none at 2 (the most
// the limb's region reaches beside it: it stretches there rather than tears). Smoothsteps both.
double weight_at(const AxisPlace& at, double band) {
  const double x = std::clamp(-at.u / (2 * band), 0.0, 1.0), y = std::clamp(2 * (2 - at.rho), 0.0, 1.0);
  return x * x * (3 - 2 * x) * y * y * (3 - 2 * y);
}

}  // namespace

double RigidGrid::limb_weight(const Rider& d, const Vec2& q) { return weight_at(axis_place(d.axis, d.radius, d.hinge, q), d.band); }

void RigidGrid::skin_bones(const Character& ch) {
  const size_t n = rest_.size();
  node_bone_.assign(n, -1);
  node_bone_w_.assign(n, 0.0);
  skin_.clear();
  bool any = false;
  for (const Rider& d : riders_) any = any || d.bone;
  if (!any) return;
  std::vector<std::vector<int>> adj(n);  // the mesh's edges: nodes joined through the figure
  for (const auto& t : tris_)
    for (int k = 0; k < 3; ++k) {
      const int a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
      adj[size_t(a)].push_back(b);
      adj[size_t(b)].push_back(a);
    }
  std::vector<double> rho_of(n, INFINITY);
  std::vector<AxisPlace> at(n);
  std::vector<char> seen(n);
  std::vector<int> queue;
  for (size_t r = 0; r < riders_.size(); ++r) {
    const Rider& d = riders_[r];
    if (!d.bone || d.axis.size() < 2) continue;
    // Its limb: from the nodes on its axis, through the mesh, on the limb's side of the joint and
    // within 2 half-widths of the axis (a bump of the outline rides; another limb beside it,
    // across a gap, is not reached).
    for (size_t i = 0; i < n; ++i) at[i] = axis_place(d.axis, d.radius, d.hinge, rest_[i]);
    std::fill(seen.begin(), seen.end(), 0);
    queue.clear();
    for (size_t i = 0; i < n; ++i)
      if (at[i].u < -0.5 * d.band && at[i].rho <= 0.5) seen[i] = 1, queue.push_back(int(i));
    if (queue.empty()) {  // (a limb thinner than a cell: the node nearest its axis)
      size_t k = n;
      for (size_t i = 0; i < n; ++i)
        if (at[i].u < 0 && at[i].rho < 2 && (k == n || at[i].rho < at[k].rho)) k = i;
      if (k < n) seen[k] = 1, queue.push_back(int(k));
    }
    // (never across the joint: a cut through it, across the axis, one and a half half-widths each
    // way, stops the flood where the limb leaves what it hangs from)
    const Vec2 last = d.axis.back() - d.axis[d.axis.size() - 2];
    const Vec2 across = last.norm() > 0 ? Vec2(1.5 * d.radius.back() * Vec2(-last.y(), last.x()) / last.norm()) : Vec2(Vec2::Zero());
    const Vec2 c0 = d.hinge - across, c1 = d.hinge + across;
    auto crosses_cut = [&](const Vec2& a, const Vec2& b) {
      const double s1 = cross(c1 - c0, a - c0), s2 = cross(c1 - c0, b - c0), s3 = cross(b - a, c0 - a), s4 = cross(b - a, c1 - a);
      return ((s1 < 0) != (s2 < 0)) && ((s3 < 0) != (s4 < 0));
    };
    for (size_t q = 0; q < queue.size(); ++q)
      for (int v : adj[size_t(queue[q])])
        if (!seen[size_t(v)] && at[size_t(v)].u < 0 && at[size_t(v)].rho < 2 && !crosses_cut(rest_[size_t(queue[q])], rest_[size_t(v)]))
          seen[size_t(v)] = 1, queue.push_back(v);
    for (int i : queue) {
      if (at[size_t(i)].rho >= rho_of[size_t(i)]) continue;  // (another bone's axis is nearer)
      rho_of[size_t(i)] = at[size_t(i)].rho;
      node_bone_[size_t(i)] = int(r);
      node_bone_w_[size_t(i)] = weight_at(at[size_t(i)], d.band);
    }
  }
  // The points they carry: through the nodes each is embedded in (a bone's, the one weighing most).
  std::vector<int> pt_bone;
  std::vector<double> pt_w;
  for (size_t si = 0; si < binds_.size() && si < ch.shapes.size(); ++si) {
    if (si < rider_of_.size() && rider_of_[si] >= 0) continue;
    const SubShape& sh = ch.shapes[si];
    const size_t m = std::min(binds_[si].size(), sh.points.size());
    pt_bone.assign(m, -1);
    pt_w.assign(m, 0.0);
    // (which bone: the one whose limb's nodes it is embedded in; how much: from where the point
    // itself is, so the weight runs smoothly along an outline whatever the mesh under it)
    for (size_t k = 0; k < m; ++k)
      if (bone_weight(binds_[si][k], &pt_bone[k]) > 0 && pt_bone[k] >= 0) pt_w[k] = limb_weight(riders_[size_t(pt_bone[k])], sh.points[k]);
    // A shape the limb's region cuts across its side, not at the joint (a neck drawn under a lock
    // of hair, a shirt under an arm), would tear there: unless it holds the limb's free end, it
    // rides on the limb whole (blended at the joint) when most of it is on it, else stays off it.
    for (size_t r = 0; r < riders_.size(); ++r) {
      const Rider& d = riders_[r];
      if (!d.bone || std::find(pt_bone.begin(), pt_bone.end(), int(r)) == pt_bone.end()) continue;
      auto w_of = [&](size_t k) { return pt_bone[k] == int(r) ? pt_w[k] : 0.0; };
      bool torn = false;
      for (const Contour& c : sh.contours)
        for (int i = 0; i + 1 < c.count + (c.closed ? 1 : 0) && !torn; ++i) {
          const size_t a = size_t(c.begin + i), b = size_t(c.begin + (i + 1) % c.count);
          if (a >= m || b >= m) continue;
          const double apart = (sh.points[a] - sh.points[b]).norm();
          torn = std::abs(w_of(a) - w_of(b)) > 0.75 * apart / d.band + 0.25;
        }
      if (!torn) continue;
      bool holds = false;
      for (const Contour& c : sh.contours) {
        if (!sh.fill.enabled || c.count < 3 || size_t(c.begin + c.count) > sh.points.size()) continue;
        holds = holds || winding_number(std::span<const Vec2>(sh.points.data() + c.begin, size_t(c.count)), d.axis.front()) != 0;
      }
      if (holds) continue;
      size_t on = 0;
      for (size_t k = 0; k < m; ++k) on += w_of(k) > 0;
      const bool rides = 2 * on >= m;
      for (size_t k = 0; k < m; ++k) {
        if (rides) {  // (all of it across the limb: blended at the joint only)
          pt_bone[k] = int(r), pt_w[k] = weight_at({axis_place(d.axis, d.radius, d.hinge, sh.points[k]).u, 0.0}, d.band);
        } else if (pt_bone[k] == int(r)) {
          pt_bone[k] = -1, pt_w[k] = 0;
        }
      }
    }
    for (size_t k = 0; k < m; ++k)
      if (pt_bone[k] >= 0 && pt_w[k] > 1e-9) skin_.push_back({int(si), int(k), pt_bone[k], pt_w[k], eval(binds_[si][k])});  // (x_ is the rest)
  }
}

double RigidGrid::bone_weight(const Embed& e, int* bone) const {
  double best = 0;
  *bone = -1;
  for (int a = 0; a < e.n; ++a) {
    const int b = node_bone_[size_t(e.v[a])];
    if (b < 0) continue;
    double sum = 0;
    for (int c = 0; c < e.n; ++c) sum += node_bone_[size_t(e.v[c])] == b ? e.w[c] * node_bone_w_[size_t(e.v[c])] : 0.0;
    if (sum > best) best = std::min(sum, 1.0), *bone = b;
  }
  return best;
}

int RigidGrid::bone_at(const Vec2& rest_point) const {
  if (skin_.empty()) return -1;
  int b = -1;
  return bone_weight(embed(rest_point), &b) >= 0.5 ? b : -1;
}

// Where each hinge is on the grid, and per rider the handles on it and on all that hangs on it
// (riders are parents first).
void RigidGrid::link_riders() {
  for (size_t r = 0; r < riders_.size(); ++r) {
    Rider& d = riders_[r];
    if (d.parent >= 0 || d.still) continue;
    if (!d.bone)  // a rider hinged on a bone's limb hangs on the bone (the bones come first)
      if (const int b = bone_at(d.hinge); b >= 0 && size_t(b) < r) {
        d.parent = b;
        continue;
      }
    d.at = embed(d.hinge);
    d.at0 = eval(d.at);  // (x_ is the rest)
    double best = INFINITY;  // the grid's turn at the hinge: the nearest node 1.5 cells or more from it
    for (size_t k = 0; k < rest_.size(); ++k) {
      const double dist = (rest_[k] - d.hinge).norm();
      if (dist >= 1.5 * h_ && dist < best && (!d.bone || node_bone_[k] != int(r))) best = dist, d.ref = int(k);
    }
    d.refs.clear();
    if (d.bone) {  // a bone: the grid's turn beside its joint, off its limb (the body there)
      const double around = std::max(3 * h_, 2 * d.radius.back());
      for (size_t k = 0; k < rest_.size() && d.refs.size() < 64; ++k)
        if (const double dist = (rest_[k] - d.hinge).norm(); dist >= 0.5 * h_ && dist <= around && node_bone_[k] < 0) d.refs.push_back(int(k));
    }
  }
  pull_start_.assign(1, 0);
  desc_start_.assign(1, 0);
  pull_h_.clear(), pull_r_.clear(), desc_.clear();
  std::vector<std::vector<int>> below(riders_.size());  // (each rider, up its ancestors: n times the depth)
  for (size_t q = 0; q < riders_.size(); ++q)
    for (int a = int(q); a >= 0; a = riders_[size_t(a)].parent) below[size_t(a)].push_back(int(q));
  for (size_t r = 0; r < riders_.size(); ++r) {
    for (int q : below[r]) {
      if (q != int(r)) desc_.push_back(q);
      const int h = riders_[size_t(q)].handle;
      if (h >= 0 && size_t(h) < handle_rest_.size()) pull_h_.push_back(h), pull_r_.push_back(q);
    }
    pull_start_.push_back(int(pull_h_.size()));
    desc_start_.push_back(int(desc_.size()));
  }
}

void RigidGrid::place_riders(std::span<const Vec2> targets) {
  // Where each hangs now, turned as drawn against what it hangs on (the grid's turn at its
  // hinge, or its parent rider's). Every frame starts so: the pose is the targets' alone, so
  // targets back where they began bring every rider back as drawn (kept from the last frame,
  // a chain swung far could settle folded, each link pointing at its target).
  for (Rider& d : riders_) {
    double base = 0;
    if (d.still) {  // (scenery: as drawn, whatever the grid does)
      d.t = d.hinge;
      d.turn(0);
      continue;
    }
    if (d.parent >= 0) {
      const Rider& p = riders_[size_t(d.parent)];
      base = p.angle;
      d.t = p.apply(d.hinge);
    } else {
      // (a hinge off the grid's figure is extrapolated, not exactly itself at rest: its moves)
      const Vec2 at = eval(d.at);
      d.t = d.hinge + (at - d.at0);
      double cs = 0, sn = 0;
      auto turn_at = [&](int k) {
        const Vec2 a = rest_[size_t(k)] - d.at0, b = x_[size_t(k)] - at;
        cs += a.dot(b);
        sn += cross(a, b);
      };
      if (!d.refs.empty())
        for (int k : d.refs) turn_at(k);
      else if (d.ref >= 0)
        turn_at(d.ref);
      if (std::isfinite(cs) && std::isfinite(sn) && (cs != 0 || sn != 0)) base = std::atan2(sn, cs);
    }
    if (!d.t.allFinite() || !std::isfinite(base)) d.t = d.hinge, base = 0;
    d.base = base;
    d.base_c = std::cos(base);
    d.base_s = std::sin(base);
    d.rel = 0;
    d.turn(base);
  }
  // Then a few sweeps, the outermost first: each turns, with all that hangs on it, about its
  // hinge to bring the handles on them (and a pen holding one) nearest their targets (least
  // squares: a hand's target swings the arm too, held back by the arm's own).
  const bool pen = grab_rider_ >= 0 && targets.size() > handles_.size() && targets[handles_.size()].allFinite();
  for (int sweep = 0; sweep < kRiderSweeps; ++sweep)
    for (size_t k = riders_.size(); k-- > 0;) {
      Rider& d = riders_[k];
      if (d.still) continue;
      double cs = 0, sn = 0;
      auto pull = [&](const Vec2& now, const Vec2& target, double w) {
        const Vec2 a = now - d.t, b = target - d.t;
        cs += w * a.dot(b);
        sn += w * cross(a, b);
      };
      for (int q = pull_start_[k]; q < pull_start_[k + 1]; ++q) {
        const size_t h = size_t(pull_h_[size_t(q)]);
        if (h < targets.size() && targets[h].allFinite())
          pull(riders_[size_t(pull_r_[size_t(q)])].apply(handle_rest_[h]), targets[h], h < handle_w_.size() ? handle_w_[h] : 1.0);
      }
      if (pen)
        for (int q = grab_rider_; q >= 0; q = riders_[size_t(q)].parent)
          if (q == int(k)) pull(riders_[size_t(grab_rider_)].apply(grab_rest_), targets[handles_.size()], 1.0);
      // One with no handle of its own: a weak spring toward its drawn turn against what it hangs
      // on, so a chain its handles leave free (an upper arm under its hand's) bends at each
      // joint rather than at the one the sweeps happen to turn most.
      const double spring = d.handle < 0 ? kRiderSpring * d.reach * d.reach : 0.0;
      cs += spring * std::cos(-d.rel);
      sn += spring * std::sin(-d.rel);
      if (!std::isfinite(cs) || !std::isfinite(sn) || (cs == 0 && sn == 0)) continue;
      const double delta = std::atan2(sn, cs);
      if (delta == 0) continue;
      const double c = std::cos(delta), s = std::sin(delta);
      for (int q = desc_start_[k]; q < desc_start_[k + 1]; ++q) {
        Rider& e = riders_[size_t(desc_[size_t(q)])];
        const Vec2 v = e.t - d.t;
        e.t = d.t + Vec2(c * v.x() - s * v.y(), s * v.x() + c * v.y());
        e.turn(e.angle + delta);
      }
      d.rel += delta;
      d.turn(d.angle + delta);
    }
}

}  // namespace mar
