// Riders on the rigid grid (solve/rigid_grid.h): parts out of the mesh that turn whole about a
// hinge the grid (or another rider) carries. Read from the rig and linked at prepare; placed
// after each solve, with no allocation.
#include "solve/rigid_grid.h"

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
  for (int r : order) {
    const RigRider& d = rig.riders[size_t(r)];
    Rider x;
    x.parent = on[size_t(r)] >= 0 ? placed[size_t(on[size_t(r)])] : -1;
    x.hinge = d.at;
    x.t = d.at;
    x.handle = d.handle.empty() ? -1 : rig.find_handle(d.handle);
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

// Where each hinge is on the grid, and per rider the handles on it and on all that hangs on it
// (riders are parents first).
void RigidGrid::link_riders() {
  for (Rider& d : riders_) {
    if (d.parent >= 0) continue;
    d.at = embed(d.hinge);
    d.at0 = eval(d.at);  // (x_ is the rest)
    double best = INFINITY;  // the grid's turn at the hinge: the nearest node 1.5 cells or more from it
    for (size_t k = 0; k < rest_.size(); ++k) {
      const double r = (rest_[k] - d.hinge).norm();
      if (r >= 1.5 * h_ && r < best) best = r, d.ref = int(k);
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
    if (d.parent >= 0) {
      const Rider& p = riders_[size_t(d.parent)];
      base = p.angle;
      d.t = p.apply(d.hinge);
    } else {
      // (a hinge off the grid's figure is extrapolated, not exactly itself at rest: its moves)
      const Vec2 at = eval(d.at);
      d.t = d.hinge + (at - d.at0);
      if (d.ref >= 0) {
        const Vec2 a = rest_[size_t(d.ref)] - d.at0, b = x_[size_t(d.ref)] - at;
        const double cs = a.dot(b), sn = cross(a, b);
        if (std::isfinite(cs) && std::isfinite(sn) && (cs != 0 || sn != 0)) base = std::atan2(sn, cs);
      }
    }
    if (!d.t.allFinite() || !std::isfinite(base)) d.t = d.hinge, base = 0;
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
