#include "app/loop/physics.h"

#include "app/show_toml.h"

#include <algorithm>
#include <cmath>

namespace mar {

void read_physics(const std::string& path, const toml::table& root, ShowConfig& s) {
  using namespace showtoml;
  const toml::node* n = root.get("physics");
  if (!n) return;
  const toml::table* t = n->as_table();
  if (!t) throw ShowError{at(path, *n) + ": [physics] must be a table"};
  check_keys(path, *t, {"rate", "gravity", "wind", "sync"}, "[physics]");
  if (const toml::node* sy = t->get("sync")) {
    const std::string v = text(path, *sy, "sync");
    if (v != "beat" && v != "time") throw ShowError{at(path, *sy) + ": sync must be \"beat\" or \"time\""};
    s.physics.sync_beat = v == "beat";
  }
  if (const toml::node* r = t->get("rate")) {
    s.physics.rate = number(path, *r, "rate");
    if (s.physics.rate < 30 || s.physics.rate > 240) throw ShowError{at(path, *r) + ": rate must be 30..240 (steps per second)"};
  }
  if (const toml::node* g = t->get("gravity")) s.physics.gravity = point(path, *g, "gravity");
  if (const toml::node* w = t->get("wind")) s.physics.wind = point(path, *w, "wind");
}

void chain_parent_pose(const Puppet& p, const PuppetChain& pc, Vec2& anchor, double& rotation) {
  // The best rigid motion of the parent's points from the drawing (2D Procrustes), weighted
  // toward where the chain hangs.
  const Points& now = p.shapes[size_t(pc.geo.parent)];
  const Points& drawn = p.character.shapes[size_t(pc.geo.parent)].points;
  const Vec2 a0 = pc.geo.rest[0];
  const double s2 = pc.reach * pc.reach;
  const size_t n = std::min(drawn.size(), now.size());
  double wsum = 0;
  Vec2 cd = Vec2::Zero(), cn = Vec2::Zero();
  for (size_t k = 0; k < n; ++k) {
    const double wk = 1.0 / (1.0 + (drawn[k] - a0).squaredNorm() / s2);
    wsum += wk;
    cd += wk * drawn[k];
    cn += wk * now[k];
  }
  cd /= std::max(wsum, 1e-300);
  cn /= std::max(wsum, 1e-300);
  double sxx = 0, sxy = 0;
  for (size_t k = 0; k < n; ++k) {
    const double wk = 1.0 / (1.0 + (drawn[k] - a0).squaredNorm() / s2);
    const Vec2 d = drawn[k] - cd, m = now[k] - cn;
    sxx += wk * d.dot(m);
    sxy += wk * (d.x() * m.y() - d.y() * m.x());
  }
  rotation = std::atan2(sxy, sxx);
  const double c = std::cos(rotation), s = std::sin(rotation);
  const Vec2 off = a0 - cd;
  anchor = cn + Vec2(c * off.x() - s * off.y(), s * off.x() + c * off.y());
}

void PhysicsStage::prepare(const Puppet& p, const ShowPhysics& world) {
  world_ = world;
  h_ = 1.0 / std::clamp(world.rate, 30.0, 240.0);
  chains_.clear();
  for (const PuppetChain& pc : p.chains) {
    const RigPhysics& ph = *pc.spec;
    ChainParams cp;
    cp.model = ph.spring ? ChainParams::Spring : ChainParams::Pendulum;
    cp.frequency = ph.frequency >= 0 ? ph.frequency : (ph.spring ? 2.0 : 0.0);
    cp.damping = ph.damping;
    cp.inertia = ph.inertia;
    cp.mass = ph.mass;
    cp.mix = ph.mix;
    cp.limit = ph.limit;
    Item it{ph.name, Chain(pc.geo.rest, cp), cp, ph.has_gravity, ph.gravity, ph.wind, ph.gust, 0};
    chains_.push_back(std::move(it));
  }
  t_ = 0;
  gravity_scale_ = 1;
  reset_ = true;
}

std::vector<PhysicsStage::SettingInfo> PhysicsStage::setting_names(const Puppet& p) {
  std::vector<SettingInfo> out;
  if (p.chains.empty()) return out;
  for (const PuppetChain& c : p.chains) {
    out.push_back({"physics." + c.spec->name + ".strength", 1, 0, 2});
    out.push_back({"physics." + c.spec->name + ".mix", c.spec->mix, 0, 1});
  }
  out.push_back({"physics.wind", 0, -2000, 2000});
  out.push_back({"physics.gravity", 1, 0, 2});
  out.push_back({"physics.reset", 0, 0, 1});
  return out;
}

std::vector<PhysicsStage::SettingInfo> PhysicsStage::settings() const {
  std::vector<SettingInfo> out;
  if (chains_.empty()) return out;
  for (const Item& it : chains_) {
    out.push_back({"physics." + it.name + ".strength", 1, 0, 2});
    out.push_back({"physics." + it.name + ".mix", it.base.mix, 0, 1});
  }
  out.push_back({"physics.wind", world_.wind.x(), -2000, 2000});
  out.push_back({"physics.gravity", 1, 0, 2});
  out.push_back({"physics.reset", 0, 0, 1});
  return out;
}

void PhysicsStage::set(size_t k, double v) {
  const size_t per = 2 * chains_.size();
  if (k < per) {
    Item& it = chains_[k / 2];
    if (k % 2 == 0) it.chain.params().inertia = it.base.inertia * std::clamp(v, 0.0, 2.0);
    else it.chain.params().mix = std::clamp(v, 0.0, 1.0);
  } else if (k == per) {
    world_.wind.x() = v;
  } else if (k == per + 1) {
    gravity_scale_ = std::clamp(v, 0.0, 2.0);
  } else if (k == per + 2) {
    if (v >= 0.5 && reset_level_ < 0.5) reset_ = true;  // on the press
    reset_level_ = v;
  }
}

void PhysicsStage::step(double dt, const Puppet& p, std::span<Vec2> targets) {
  t_ += std::max(0.0, dt);
  for (size_t c = 0; c < chains_.size(); ++c) {
    Item& it = chains_[c];
    const PuppetChain& pc = p.chains[c];
    Vec2 seen;
    double rot = 0;
    chain_parent_pose(p, pc, seen, rot);
    rot = it.rotation + std::remainder(rot - it.rotation, 2 * M_PI);  // unwrapped: no jump at +-pi
    it.rotation = rot;
    // The pose read is the last frame's: where the parent is now, it goes on as it went (this
    // frame's solve moves it once more), so the chain does not trail it by a frame.
    const bool going = !reset_ && it.seen_before;
    const Vec2 anchor = going ? Vec2(2 * seen - it.last_seen) : seen;
    const double turned = going ? 2 * rot - it.last_rotation : rot;
    it.last_seen = seen;
    it.last_rotation = rot;
    it.seen_before = true;
    MotionWorld w;
    w.gravity = (it.own_gravity ? it.gravity : world_.gravity) * gravity_scale_;
    // On the beat (sync): the show's wind and the gusts in a pulse, strongest on each beat.
    const double pulse = world_.sync_beat ? 0.5 + 0.5 * std::cos(2 * M_PI * beats_) : 1.0;
    Vec2 wind = world_.wind * pulse + it.wind;
    if (it.gust > 0) {  // gusts along the wind (across when there is none), smooth and the same each run
      const Vec2 along = wind.norm() > 1e-9 ? Vec2(wind.normalized()) : Vec2(1, 0);
      wind += along * (it.gust * (world_.sync_beat ? pulse : smooth_noise(1.3 * t_, double(c) + 1)));
    }
    w.wind = wind;
    if (reset_) it.chain.reset(anchor, turned);
    else it.chain.advance(dt, h_, anchor, turned, w);
    const auto ends = it.chain.ends();
    for (size_t i = 0; i < ends.size() && i < pc.handles.size(); ++i)
      if (pc.handles[i] < targets.size()) targets[pc.handles[i]] = ends[i];
  }
  reset_ = false;
}

long PhysicsStage::steps() const {
  long n = 0;
  for (const Item& it : chains_) n += it.chain.steps();
  return n;
}
long PhysicsStage::resets() const {
  long n = 0;
  for (const Item& it : chains_) n += it.chain.resets();
  return n;
}
long PhysicsStage::reverts() const {
  long n = 0;
  for (const Item& it : chains_) n += it.chain.reverts();
  return n;
}

void PhysicsStage::carry_from(const PhysicsStage& old) {
  for (Item& c : chains_)
    for (const Item& o : old.chains_) {
      if (o.name != c.name || o.chain.links() != c.chain.links()) continue;
      const ChainParams params = c.chain.params();
      c.chain = o.chain;
      c.chain.params() = params;
      c.rotation = o.rotation;
      c.last_seen = o.last_seen;
      c.last_rotation = o.last_rotation;
      c.seen_before = o.seen_before;
    }
  t_ = old.t_;
  beats_ = old.beats_;
  reset_ = old.reset_;
}

}  // namespace mar
