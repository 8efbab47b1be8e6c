#include "app/loop/idle.h"

#include "app/show_toml.h"

#include <algorithm>
#include <cmath>

namespace mar {

void read_behaviors(const std::string& path, const toml::table& root, ShowConfig& s, const ShowRig& rig) {
  using namespace showtoml;
  const toml::node* n = root.get("behavior");
  if (!n) return;
  const toml::array* a = n->as_array();
  if (!a) throw ShowError{at(path, *n) + ": use [[behavior]] tables"};
  for (const toml::node& node : *a) {
    const toml::table* t = node.as_table();
    if (!t) throw ShowError{at(path, node) + ": a behavior must be a table"};
    check_keys(path, *t, {"name", "kind", "target", "mean", "jitter", "hold", "seed", "period", "depth", "range", "speed", "resume", "fade", "sync"},
               "[[behavior]]");
    ShowBehavior b;
    b.line = int(node.source().begin.line);
    const toml::node* kind = t->get("kind");
    if (!kind) throw ShowError{at(path, node) + ": a behavior needs kind = \"blink\", \"breathe\", \"look\" or \"sway\""};
    const std::string k = text(path, *kind, "kind");
    if (k == "blink") b.spec.kind = BehaviorSpec::Blink;
    else if (k == "breathe") b.spec.kind = BehaviorSpec::Breathe;
    else if (k == "look" || k == "sway") b.spec.kind = BehaviorSpec::Look;
    else throw ShowError{at(path, *kind) + ": kind must be blink, breathe, look or sway"};
    b.name = k;
    if (const toml::node* nm = t->get("name")) b.name = text(path, *nm, "name");
    const toml::node* tg = t->get("target");
    if (!tg) throw ShowError{at(path, node) + ": behavior '" + b.name + "' needs a target"};
    b.target_text = text(path, *tg, "target");
    if (auto r = parse_target(b.target_text, s, rig, b.target, b.index, &b.member); !r.ok()) throw ShowError{at(path, *tg) + ": " + r.error};
    const bool blink = b.spec.kind == BehaviorSpec::Blink;
    const bool shows = b.target == TargetKind::Trigger || b.target == TargetKind::Swap;
    const bool moves = b.target == TargetKind::HandleX || b.target == TargetKind::HandleY || b.target == TargetKind::HandlePoint ||
                       b.target == TargetKind::Rotate || b.target == TargetKind::Setting;
    if (blink && !shows) throw ShowError{at(path, *tg) + ": a blink shows something: target trigger.NAME or swap.SET.MEMBER"};
    if (!blink && !moves)
      throw ShowError{at(path, *tg) + ": " + k + " moves something: target handle.NAME[.x|.y], rotate.GROUP or a setting (blend.KEY, ...)"};
    auto positive = [&](const char* key, double& v, double lo, double hi) {
      if (const toml::node* x = t->get(key)) {
        v = number(path, *x, key);
        if (!(v >= lo && v <= hi)) {
          char r[64];
          std::snprintf(r, sizeof r, "%g..%g", lo, hi);
          throw ShowError{at(path, *x) + ": " + key + " must be " + r};
        }
      }
    };
    positive("mean", b.spec.mean, 0.1, 3600);
    positive("jitter", b.spec.jitter, 0, 0.95);
    positive("hold", b.spec.hold, 0.01, 10);
    positive("period", b.spec.period, 0.1, 3600);
    positive("speed", b.spec.speed, 0.001, 10);
    positive("resume", b.spec.resume, 0, 3600);
    positive("fade", b.spec.fade, 0, 60);
    if (const toml::node* sy = t->get("sync")) {  // on the music: period, mean in beats, speed per beat
      const std::string v = text(path, *sy, "sync");
      if (v != "beat" && v != "time") throw ShowError{at(path, *sy) + ": sync must be \"beat\" or \"time\""};
      b.spec.sync_beat = v == "beat";
    }
    if (const toml::node* sd = t->get("seed")) b.spec.seed = uint64_t(integer(path, *sd, "seed", 0, 2147483647));
    // depth (breathe) and range (look): [x, y] for a handle, a number for anything else
    for (const char* key : {"depth", "range"}) {
      const toml::node* x = t->get(key);
      if (!x) continue;
      if ((std::string(key) == "depth") != (b.spec.kind == BehaviorSpec::Breathe))
        throw ShowError{at(path, *x) + ": " + key + " is for " + (std::string(key) == "depth" ? "breathe" : "look and sway")};
      Vec2& v2 = std::string(key) == "depth" ? b.spec.depth : b.spec.range;
      if (b.target == TargetKind::HandlePoint) {
        v2 = point(path, *x, key);
      } else {
        b.spec.amount = number(path, *x, key);
        if (b.target == TargetKind::HandleX) v2 = Vec2(b.spec.amount, 0);
        if (b.target == TargetKind::HandleY) v2 = Vec2(0, b.spec.amount);
      }
    }
    // Defaults that fit the target when none is given.
    if (!t->get("depth") && b.spec.kind == BehaviorSpec::Breathe) {
      if (b.target == TargetKind::HandleX) b.spec.depth = Vec2(3, 0);
      if (b.target == TargetKind::Setting) b.spec.amount = 1;
      if (b.target == TargetKind::Rotate) b.spec.amount = 2;
    }
    if (!t->get("range") && b.spec.kind == BehaviorSpec::Look) {
      if (b.target == TargetKind::HandleX) b.spec.range = Vec2(8, 0);
      if (b.target == TargetKind::HandleY) b.spec.range = Vec2(0, 4);
      if (b.target == TargetKind::Rotate) b.spec.amount = 6;
      if (b.target == TargetKind::Setting) b.spec.amount = 0.3;
    }
    if (blink && !t->get("seed")) b.spec.seed = uint64_t(s.behaviors.size() + 1);
    s.behaviors.push_back(std::move(b));
  }
}

namespace {

// Whether a binding writes the target a behaviour drives (a handle's axis counts for the handle).
bool same_target(const Binding& b, const ShowBehavior& sb) {
  const auto handle = [](TargetKind k) { return k == TargetKind::HandleX || k == TargetKind::HandleY || k == TargetKind::HandlePoint; };
  if (handle(b.target) && handle(sb.target)) return b.index == sb.index;
  return b.target == sb.target && b.index == sb.index;
}

}  // namespace

void IdleStage::prepare(const ShowConfig& show, const Mapping& m) {
  items_.clear();
  blinks_ = false;
  for (const ShowBehavior& sb : show.behaviors) {
    Item it{Behavior(sb.spec), sb.target, sb.index, sb.member, {}, 0};
    for (size_t i = 0; i < m.binding_count(); ++i)
      if (same_target(m.binding(i), sb)) it.writers.push_back(i);
    blinks_ = blinks_ || sb.spec.kind == BehaviorSpec::Blink;
    items_.push_back(std::move(it));
  }
  first_ = true;
}

void IdleStage::step(double dt, const Mapping& m, double beats) {
  for (Item& it : items_) {
    uint64_t hits = 0;
    for (size_t w : it.writers) hits += m.binding(w).hits;
    const bool touched = !first_ && hits != it.hits;
    it.hits = hits;
    it.b.step(dt, touched, beats);
  }
}

double IdleStage::setting_offset(int i) const {
  double v = 0;
  for (const Item& it : items_)
    if (it.target == TargetKind::Setting && it.index == i) v += it.b.value();
  return v;
}

void IdleStage::apply_targets(std::span<Vec2> targets, const std::vector<RotationGroup>& groups, std::span<const Vec2> pivots) const {
  constexpr double kDeg = M_PI / 180;
  for (const Item& it : items_) {
    if (it.b.spec().kind == BehaviorSpec::Blink) continue;
    if (it.target == TargetKind::HandleX || it.target == TargetKind::HandleY || it.target == TargetKind::HandlePoint) {
      if (size_t(it.index) < targets.size()) targets[size_t(it.index)] += it.b.offset();
    } else if (it.target == TargetKind::Rotate && size_t(it.index) < groups.size()) {
      const RotationGroup& g = groups[size_t(it.index)];
      // (about where the mapping turned it: a group that follows a handle has moved its pivot)
      const Vec2 pivot = g.pivot_handle >= 0 && size_t(g.pivot_handle) < targets.size() ? targets[size_t(g.pivot_handle)]
                         : size_t(it.index) < pivots.size()                             ? pivots[size_t(it.index)]
                                                                                        : g.pivot;
      const double a = it.b.value() * kDeg, c = std::cos(a), s = std::sin(a);
      for (int h : g.handles) {
        if (size_t(h) >= targets.size()) continue;
        const Vec2 r = targets[size_t(h)] - pivot;
        targets[size_t(h)] = pivot + Vec2(c * r.x() - s * r.y(), s * r.x() + c * r.y());
      }
    }
  }
}

bool IdleStage::shown(std::span<const int> members, std::span<const char> triggers) {
  members_.assign(members.begin(), members.end());  // (sized at the first call: no allocation after)
  triggers_.assign(triggers.begin(), triggers.end());
  for (const Item& it : items_) {
    if (!it.b.on()) continue;
    if (it.target == TargetKind::Trigger && size_t(it.index) < triggers_.size()) triggers_[size_t(it.index)] = 1;
    if (it.target == TargetKind::Swap && size_t(it.index) < members_.size()) members_[size_t(it.index)] = it.member;
  }
  const bool changed = first_ || members_ != last_members_ || triggers_ != last_triggers_;
  last_members_ = members_;
  last_triggers_ = triggers_;
  first_ = false;
  return changed;
}

}  // namespace mar
