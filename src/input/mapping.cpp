#include "input/mapping.h"

#include <algorithm>
#include <cmath>

namespace mar {
namespace {
constexpr double kDeg = M_PI / 180.0;
}

double ease(Ease e, double s) {
  s = std::clamp(s, 0.0, 1.0);
  switch (e) {
    case Ease::Linear: return s;
    case Ease::In: return s * s * s;
    case Ease::Out: return 1 - (1 - s) * (1 - s) * (1 - s);
    case Ease::InOut: return s < 0.5 ? 4 * s * s * s : 1 - 4 * (1 - s) * (1 - s) * (1 - s);
  }
  return s;
}

void Mapping::set_handles(std::vector<std::string> names, std::vector<Vec2> rest) {
  names_ = std::move(names);
  rest_ = rest;
  goal_ = rest;
  current_ = rest;
  anim_.assign(rest.size(), Anim{});
  targets_ = std::move(rest);
}

void Mapping::carry_from(const Mapping& old) {
  // Handles and rotations by name stay where they were; a binding whose control is the same
  // keeps what it knew of that control, and an absolute one that had picked its target up sets
  // it at once with its new range (the edit shows without the control moving).
  for (size_t i = 0; i < names_.size(); ++i) {
    const int j = old.handle_index(names_[i]);
    if (j < 0) continue;
    goal_[i] = old.goal_[size_t(j)];
    current_[i] = old.current_[size_t(j)];
    targets_[i] = old.targets_[size_t(j)];
  }
  for (size_t g = 0; g < groups_.size(); ++g) {
    const int j = old.group_index(groups_[g].name);
    if (j < 0) continue;
    angle_goal_[g] = old.angle_goal_[size_t(j)];
    angle_[g] = old.angle_[size_t(j)];
  }
  for (Binding& b : bindings_) {
    for (const Binding& o : old.bindings_) {
      const ControlSpec &x = b.control, &y = o.control;
      if (x.device != y.device || x.kind != y.kind || x.number != y.number || x.channel != y.channel) continue;
      b.last_norm = o.last_norm;
      b.toggled = o.toggled;
      b.pressed = o.pressed;
      b.msb = o.msb;
      b.lsb = o.lsb;
      b.nrpn_hi = o.nrpn_hi;
      b.nrpn_param = o.nrpn_param;
      b.px = o.px;
      b.py = o.py;
      b.tip = o.tip;
      const bool continuous = !button_target(b.target) && b.target != TargetKind::Grab && b.target != TargetKind::Brush && b.target != TargetKind::Curve &&
                              b.target != TargetKind::HandlePoint;
      if (continuous && o.engaged && o.last_norm >= 0) {
        b.engaged = true;
        set_target(b, b.tf.lo + o.last_norm * (b.tf.hi - b.tf.lo));
      }
      break;
    }
  }
}

void Mapping::set_swaps(std::vector<int> member_counts, std::vector<int> defaults, size_t triggers) {
  swap_count_ = std::move(member_counts);
  swap_now_ = std::move(defaults);
  swap_now_.resize(swap_count_.size(), 0);
  trigger_on_.assign(triggers, 0);
}

void Mapping::ease_handle(int h, const Vec2& to, double seconds, Ease e) {
  Anim& a = anim_[size_t(h)];
  a.from = goal_[size_t(h)];
  a.to = to;
  a.t = 0;
  a.seconds = seconds;
  a.ease = e;
  a.on = seconds > 0;
  if (!a.on) goal_[size_t(h)] = to;
}

int Mapping::handle_index(const std::string& name) const {
  for (size_t i = 0; i < names_.size(); ++i)
    if (names_[i] == name) return int(i);
  return -1;
}

int Mapping::add_group(RotationGroup g) {
  pivots_.push_back(g.pivot);
  groups_.push_back(std::move(g));
  angle_goal_.push_back(0);
  angle_.push_back(0);
  return int(groups_.size()) - 1;
}

int Mapping::group_index(const std::string& name) const {
  for (size_t i = 0; i < groups_.size(); ++i)
    if (groups_[i].name == name) return int(i);
  return -1;
}

int Mapping::add_pose(Pose p) {
  poses_.push_back(std::move(p));
  return int(poses_.size()) - 1;
}

int Mapping::pose_index(const std::string& name) const {
  for (size_t i = 0; i < poses_.size(); ++i)
    if (poses_[i].name == name) return int(i);
  return -1;
}

void Mapping::add_binding(Binding b) {
  bindings_.push_back(std::move(b));
  Binding& nb = bindings_.back();
  if (!arbitrable(nb.target)) return;
  // Arbitrated when two or more bindings drive the target and one of them states a priority
  // (a lone binding has nobody to share with: it keeps soft takeover).
  std::vector<int> on;
  bool stated = false;
  for (size_t k = 0; k < bindings_.size(); ++k)
    if (bindings_[k].target == nb.target && bindings_[k].index == nb.index) {
      on.push_back(int(k));
      stated = stated || bindings_[k].tf.has_priority;
    }
  if (on.size() < 2 || !stated) return;
  int a = -1;
  for (size_t k = 0; k < arbs_.size(); ++k)
    if (arbs_[k].kind == nb.target && arbs_[k].index == nb.index) a = int(k);
  if (a < 0) {
    arbs_.push_back({nb.target, nb.index, {}, {}});
    a = int(arbs_.size()) - 1;
  }
  ArbTarget& at = arbs_[size_t(a)];
  at.bindings = std::move(on);
  std::vector<SourcePriority> sources;
  for (size_t k = 0; k < at.bindings.size(); ++k) {
    Binding& src = bindings_[size_t(at.bindings[k])];
    src.arb = a;
    src.arb_source = int(k);
    sources.push_back(src.tf.priority);
  }
  at.arb.set_sources(std::move(sources));
}

double Mapping::raw(TargetKind k, int index) const {
  const size_t i = size_t(index);
  switch (k) {
    case TargetKind::HandleX: return goal_[i].x();
    case TargetKind::HandleY: return goal_[i].y();
    case TargetKind::Rotate: return angle_goal_[i];
    case TargetKind::Setting: return settings_[i].value;
    default: return 0;
  }
}

void Mapping::put(TargetKind k, int index, double v) {
  const size_t i = size_t(index);
  switch (k) {
    case TargetKind::HandleX: goal_[i].x() = v; break;
    case TargetKind::HandleY: goal_[i].y() = v; break;
    case TargetKind::Rotate: angle_goal_[i] = v; break;
    case TargetKind::Setting: put_setting(i, v); break;
    default: break;
  }
}

void Mapping::arbitrated(Binding& b, double v) {
  // Its own value always; the target's only while it holds it (a hand-over eases in update()).
  Arbiter& a = arbs_[size_t(b.arb)].arb;
  a.write(b.arb_source, v, clock_);
  if (a.holder() != b.arb_source) return;
  put(b.target, b.index, a.value());
  written_by(&b, b.target, b.index);
}

int Mapping::holds(size_t i) const {
  const Binding& b = bindings_[i];
  if (b.arb < 0) return -1;
  return arbs_[size_t(b.arb)].arb.holder() == b.arb_source ? 1 : 0;
}

bool Mapping::apply(const Event& e) {
  ++stats_.events;
  bool used = false;
  for (Binding& b : bindings_) {
    const ControlSpec& c = b.control;
    if (c.device != e.source) continue;
    const bool chan = c.channel < 0 || c.channel == e.channel;
    bool hit = false;
    switch (c.kind) {
      case ControlSpec::CC:
        if (e.kind == ControlKind::MidiCC && e.number == c.number && chan) {
          hit = true;
          if (b.tf.relative != RelativeMode::Absolute)
            relative(b, relative_delta(b.tf.relative, e.value));
          else if (button_target(b.target) || b.tf.toggle)
            button(b, e.value / 127.0 >= b.tf.threshold);
          else
            absolute(b, e.value / 127.0, e.t_ns);
        }
        break;
      case ControlSpec::CC14:
        if (e.kind == ControlKind::MidiCC && chan && (e.number == c.number || e.number == c.number + 32)) {
          hit = true;
          fourteen_bit(b, e.number == c.number, e.value, e.t_ns);
        }
        break;
      case ControlSpec::NRPN:
        if (e.kind == ControlKind::MidiCC && chan) {
          if (e.number == 99) {
            b.nrpn_hi = e.value;
            b.nrpn_param = -1;
          } else if (e.number == 98) {
            b.nrpn_param = (b.nrpn_hi << 7) | e.value;
          } else if ((e.number == 6 || e.number == 38) && b.nrpn_param == int(c.number)) {
            hit = true;
            fourteen_bit(b, e.number == 6, e.value, e.t_ns);
          }
        }
        break;
      case ControlSpec::Note:
        if ((e.kind == ControlKind::MidiNoteOn || e.kind == ControlKind::MidiNoteOff) && e.number == c.number && chan) {
          hit = true;
          button(b, e.kind == ControlKind::MidiNoteOn);
        }
        break;
      case ControlSpec::NoteVelocity:
        if ((e.kind == ControlKind::MidiNoteOn || e.kind == ControlKind::MidiNoteOff) && e.number == c.number && chan) {
          hit = true;
          const double v = e.kind == ControlKind::MidiNoteOn ? e.value / 127.0 : 0.0;
          if (button_target(b.target) || b.tf.toggle) button(b, e.kind == ControlKind::MidiNoteOn && v >= b.tf.threshold);
          else absolute(b, v, e.t_ns);
        }
        break;
      case ControlSpec::Aftertouch:
      case ControlSpec::PolyPressure:
        if (chan && ((c.kind == ControlSpec::Aftertouch && e.kind == ControlKind::MidiChannelPressure) ||
                     (c.kind == ControlSpec::PolyPressure && e.kind == ControlKind::MidiPolyPressure && e.number == c.number))) {
          hit = true;
          if (button_target(b.target) || b.tf.toggle) button(b, e.value / 127.0 >= b.tf.threshold);
          else absolute(b, e.value / 127.0, e.t_ns);
        }
        break;
      case ControlSpec::Beat:
      case ControlSpec::Bar:
        if (e.kind == ControlKind::ClockPhase && e.number == (c.kind == ControlSpec::Beat ? kClockBeat : kClockBar)) {
          hit = true;
          const double v = double(e.value) / kClockPhaseMax;
          if (button_target(b.target) || b.tf.toggle) button(b, v < 0.25);  // pressed for the first quarter of each beat
          else absolute(b, v, e.t_ns);
        }
        break;
      case ControlSpec::PitchBend:
        if (e.kind == ControlKind::MidiPitchBend && chan) {
          hit = true;
          absolute(b, e.value / 16383.0, e.t_ns);
        }
        break;
      case ControlSpec::Hid:
        if (e.number != c.number) break;
        if (e.kind == ControlKind::EncoderDelta) {
          hit = true;
          relative(b, e.value);
        } else if (e.kind == ControlKind::HidValue) {
          hit = true;
          if (b.tf.relative != RelativeMode::Absolute)
            relative(b, e.value);
          else if (button_target(b.target) || b.tf.toggle || (e.lo == 0 && e.hi == 1))
            button(b, e.hi > e.lo ? normalized(e) >= b.tf.threshold : e.value != 0);
          else
            absolute(b, normalized(e), e.t_ns);
        }
        break;
      case ControlSpec::Encoder:
        if (e.kind == ControlKind::EncoderDelta && e.number == c.number) {
          hit = true;
          relative(b, e.value);
        }
        break;
      case ControlSpec::GpioButton:
        if (e.kind == ControlKind::Button && e.number == c.number) {
          hit = true;
          button(b, e.value != 0);
        }
        break;
      case ControlSpec::Pointer: {
        if (e.kind != ControlKind::HidValue) break;
        bool pressed = false;  // this event put the tip down
        if (e.number == c.px) {
          b.px = normalized(e);
        } else if (e.number == c.py) {
          b.py = normalized(e);
        } else if (e.number == c.ppressure) {
          b.pressure = normalized(e);
        } else if (e.number == c.ptip) {
          const bool was = b.tip;
          b.tip = e.value != 0;
          pressed = b.tip && !was;
          if (was && !b.tip && b.target == TargetKind::HandlePoint && b.tf.ret >= 0)  // released: back to rest
            ease_handle(b.index, rest_[size_t(b.index)], b.tf.ret, b.tf.ease);
        } else {
          break;
        }
        hit = true;
        {
          const double* a = b.tf.area;
          const double* m = b.tf.canvas_map;
          const Vec2 p = b.tf.area_canvas ? Vec2(m[0] * b.px + m[2] * b.py + m[4], m[1] * b.px + m[3] * b.py + m[5])
                                          : Vec2(a[0] + b.px * (a[2] - a[0]), a[1] + b.py * (a[3] - a[1]));
          // One pen grabs at a time: the one holding, or any while none does, or one whose tip
          // just went down (it takes over).
          const int bi = int(&b - bindings_.data());
          if (b.target == TargetKind::Grab && (grab_by_ == bi || grab_by_ < 0 || pressed)) {
            grab_active_ = b.tip;
            grab_point_ = p;
            grab_who_ = b.index;
            grab_by_ = b.tip ? bi : -1;
          } else if ((b.target == TargetKind::Brush || b.target == TargetKind::Curve) &&
                     (brush_by_ == bi || brush_by_ < 0 || pressed)) {
            // One pen with tools on several characters: its tip going down takes the tool whose
            // character is drawn under it (another pen's tip still takes over, as a grab does).
            if (pressed && pen_hit_ && brush_by_ != bi) {
              const bool under = pen_hit_(b.index, p);
              if (brush_by_ >= 0 && brush_hit_ && bindings_[size_t(brush_by_)].control.device == b.control.device) break;
              brush_hit_ = under;
            }
            brush_.down = b.tip;
            brush_.curve = b.target == TargetKind::Curve;
            brush_.point = p;
            brush_.pressure = b.pressure;
            brush_.who = b.index;
            brush_.brush = b.member;
            brush_by_ = b.tip ? bi : -1;
          } else if (b.target == TargetKind::HandlePoint && b.tip) {
            goal_[size_t(b.index)] = p;
            written_by(&b, TargetKind::HandleX, b.index);
            written_by(&b, TargetKind::HandleY, b.index);
          }
        }
        break;
      }
    }
    if (hit) {
      used = true;
      ++stats_.matched;
      ++b.hits;
    }
  }
  return used;
}

void Mapping::fourteen_bit(Binding& b, bool msb, int value, int64_t t) {
  // An MSB alone is a 14-bit value with LSB 0; the LSB that follows refines it.
  if (msb) {
    b.msb = value;
    b.lsb = 0;
  } else {
    b.lsb = value;
  }
  absolute(b, ((b.msb << 7) | b.lsb) / 16383.0, t);
}

void Mapping::absolute(Binding& b, double n, int64_t t) {
  n = std::clamp(n, 0.0, 1.0);
  if (b.tf.deadzone > 0) {
    const double half = 0.5 * b.tf.deadzone, c = n - 0.5;
    n = std::fabs(c) <= half ? 0.5 : 0.5 + std::copysign((std::fabs(c) - half) / (0.5 - half) * 0.5, c);
  }
  if (b.tf.invert) n = 1 - n;
  if (b.tf.curve != 1) n = std::pow(n, b.tf.curve);
  n = b.tf.one_euro.filter(n, t);
  const bool takeover = b.tf.takeover && b.arb < 0 && !(b.target == TargetKind::Setting && settings_[size_t(b.index)].integer);
  if (takeover && !b.engaged) {
    // Soft takeover: the control picks the target up when it reaches or crosses the
    // target's current value, so a fader that was moved elsewhere cannot make it jump.
    const double cur = current_norm(b);
    const bool crossed = b.last_norm >= 0 && (b.last_norm - cur) * (n - cur) <= 0;
    b.last_norm = n;
    if (!crossed && std::fabs(n - cur) > 1.0 / 127) {
      ++stats_.takeover_waits;
      if (!b.takeover_told) {  // said once, between frames, if it is still waiting a second later
        b.takeover_told = 1;
        b.takeover_since = t;
        takeover_news_ = true;
      }
      return;
    }
    b.engaged = true;
  }
  b.last_norm = n;
  set_target(b, b.tf.lo + n * (b.tf.hi - b.tf.lo));
}

double Mapping::binding_value(size_t i) const {
  const Binding& b = bindings_[i];
  const size_t k = size_t(b.index);
  switch (b.target) {
    case TargetKind::HandleX: return goal_[k].x();
    case TargetKind::HandleY: return goal_[k].y();
    case TargetKind::Rotate: return angle_goal_[k];
    case TargetKind::Setting: return settings_[k].value;
    default: return std::nan("");
  }
}

double Mapping::takeover_at(size_t i) const {
  const Binding& b = bindings_[i];
  const bool absolute_target = b.target == TargetKind::HandleX || b.target == TargetKind::HandleY ||
                               b.target == TargetKind::Rotate || b.target == TargetKind::Setting;
  if (!absolute_target || !b.tf.takeover || b.engaged || b.last_norm < 0) return -1;
  if (b.target == TargetKind::Setting && settings_[size_t(b.index)].integer) return -1;
  // The value the control must reach, back through the binding's curve and inversion.
  double n = std::clamp(current_norm(b), 0.0, 1.0);
  if (b.tf.curve != 1 && b.tf.curve > 0) n = std::pow(n, 1.0 / b.tf.curve);
  if (b.tf.invert) n = 1 - n;
  return n;
}

double Mapping::current_norm(const Binding& b) const {
  double v = 0;
  switch (b.target) {
    case TargetKind::HandleX: v = goal_[size_t(b.index)].x(); break;
    case TargetKind::HandleY: v = goal_[size_t(b.index)].y(); break;
    case TargetKind::Rotate: v = angle_goal_[size_t(b.index)]; break;
    case TargetKind::Setting: v = settings_[size_t(b.index)].value; break;
    default: return 0;
  }
  return b.tf.hi != b.tf.lo ? (v - b.tf.lo) / (b.tf.hi - b.tf.lo) : 0;
}

void Mapping::written_by(const Binding* w, TargetKind k, int index) {
  // A control moved the handle: an ease toward a pose or rest stops there, and a pose that
  // placed it is no longer the current one.
  if (k == TargetKind::HandleX || k == TargetKind::HandleY || k == TargetKind::HandlePoint) {
    anim_[size_t(index)].on = false;
    if (current_pose_ >= 0) {
      const auto& at = poses_[size_t(current_pose_)].positions;
      if (size_t(index) < at.size() && std::isfinite(at[size_t(index)].x())) current_pose_ = -1;
    }
  }
  // Another writer moved the target: absolute controls on it must pick it up again.
  for (Binding& b : bindings_)
    if (&b != w && b.target == k && b.index == index) b.engaged = false;
}

void Mapping::set_target(Binding& b, double v) {
  if (b.arb >= 0) return arbitrated(b, v);
  const size_t i = size_t(b.index);
  switch (b.target) {
    case TargetKind::HandleX: goal_[i].x() = v; break;
    case TargetKind::HandleY: goal_[i].y() = v; break;
    case TargetKind::Rotate: angle_goal_[i] = v; break;
    case TargetKind::Setting: put_setting(i, v); break;
    default: return;
  }
  written_by(&b, b.target, b.index);
}

int Mapping::add_setting(Setting s) {
  settings_.push_back(s);
  return int(settings_.size()) - 1;
}

void Mapping::put_setting(size_t i, double v) {
  Setting& s = settings_[i];
  if (!std::isfinite(v)) return;
  v = std::clamp(v, s.lo, s.hi);
  if (s.integer) v = std::round(v);
  if (v == s.value) return;
  s.value = v;
  settings_changed_ = true;
}

void Mapping::relative(Binding& b, double d) {
  const double step = d * b.tf.step;
  const size_t i = size_t(b.index);
  if (b.arb >= 0) {  // from its own value (the target's when it has none yet)
    const double own = arbs_[size_t(b.arb)].arb.own(b.arb_source), base = std::isfinite(own) ? own : raw(b.target, b.index);
    const bool whole = b.target == TargetKind::Setting && settings_[i].integer;
    return arbitrated(b, base + (whole ? std::trunc(d) : step));
  }
  switch (b.target) {
    case TargetKind::HandleX: goal_[i].x() += step; break;
    case TargetKind::HandleY: goal_[i].y() += step; break;
    case TargetKind::Rotate: angle_goal_[i] += step; break;
    case TargetKind::Setting:
      // An integer setting moves one unit per tick; others by the binding's step.
      put_setting(i, settings_[i].value + (settings_[i].integer ? std::trunc(d) : step));
      break;
    default: return;
  }
  written_by(&b, b.target, b.index);
}

void Mapping::button(Binding& b, bool down) {
  const bool edge = down && !b.pressed, released = !down && b.pressed;
  b.pressed = down;
  switch (b.target) {
    case TargetKind::Pose: {  // every handle it names eases there
      if (!edge) return;
      const Pose& p = poses_[size_t(b.index)];
      // A group a knob has turned lets go of its turn when the pose names one of its handles:
      // they take the positions the turn gave them (nothing jumps) and ease on from there.
      for (size_t g = 0; g < groups_.size(); ++g) {
        RotationGroup& grp = groups_[g];
        bool named = false;
        for (int h : grp.handles) named = named || (size_t(h) < p.positions.size() && std::isfinite(p.positions[size_t(h)].x()));
        if (!named || (angle_[g] == 0 && angle_goal_[g] == 0)) continue;
        const double c = std::cos(angle_[g] * kDeg), sn = std::sin(angle_[g] * kDeg);
        auto turn = [&](std::vector<Vec2>& at, int h) {
          const Vec2 pivot = grp.pivot_handle >= 0 ? at[size_t(grp.pivot_handle)] : grp.pivot;
          const Vec2 r = at[size_t(h)] - pivot;
          return Vec2(pivot + Vec2(c * r.x() - sn * r.y(), sn * r.x() + c * r.y()));
        };
        for (int h : grp.handles) {
          const Vec2 now = turn(current_, h), goal = turn(goal_, h);
          current_[size_t(h)] = now;
          goal_[size_t(h)] = goal;
        }
        angle_[g] = angle_goal_[g] = 0;
      }
      for (size_t h = 0; h < p.positions.size() && h < goal_.size(); ++h)
        if (std::isfinite(p.positions[h].x())) {
          written_by(&b, TargetKind::HandleX, int(h));
          written_by(&b, TargetKind::HandleY, int(h));
          ease_handle(int(h), p.positions[h], b.tf.transition, b.tf.ease);
        }
      current_pose_ = b.index;  // (after its own writes)
      return;
    }
    case TargetKind::Recall:
      if (edge) {
        recall_ = {b.index, b.tf.transition, b.tf.ease, b.member};
        recall_pending_ = true;
      }
      return;
    case TargetKind::Swap: {  // latch: the member stays; momentary: until released
      int& now = swap_now_[size_t(b.index)];
      if (edge) {
        b.before = now;
        shown_changed_ = shown_changed_ || now != b.member;
        now = b.member;
      } else if (released && !b.tf.toggle && now == b.member) {
        shown_changed_ = shown_changed_ || now != b.before;
        now = b.before;
      }
      return;
    }
    case TargetKind::Trigger: {  // momentary: while held; toggle: each press
      char& on = trigger_on_[size_t(b.index)];
      const char next = b.tf.toggle ? char(edge ? !on : on) : char(edge ? 1 : released ? 0 : on);
      shown_changed_ = shown_changed_ || next != on;
      on = next;
      return;
    }
    default: break;
  }
  if (b.tf.toggle) {
    if (!edge) return;
    b.toggled = !b.toggled;
    set_target(b, b.toggled ? b.tf.hi : b.tf.lo);
  } else {
    set_target(b, down ? b.tf.hi : b.tf.lo);
  }
}

void Mapping::update(double dt) {
  // Arbitration: a holder that let go hands its target over; a hand-over eases.
  clock_ += std::max(0.0, dt);
  for (ArbTarget& at : arbs_) {
    const double before = at.arb.value(), v = at.arb.update(clock_, dt);
    if (!std::isfinite(v) || v == before) continue;
    put(at.kind, at.index, v);
    const int h = at.arb.holder();
    written_by(h >= 0 ? &bindings_[size_t(at.bindings[size_t(h)])] : nullptr, at.kind, at.index);
  }
  // Timed eases (a pose, a return to rest) move the goals.
  for (size_t h = 0; h < anim_.size(); ++h) {
    Anim& a = anim_[h];
    if (!a.on) continue;
    a.t += std::max(0.0, dt);
    const double s = a.t >= a.seconds * (1 - 1e-9) ? 1.0 : a.t / a.seconds;  // (frame steps add up inexactly)
    goal_[h] = s >= 1 ? a.to : Vec2(a.from + ease(a.ease, s) * (a.to - a.from));
    if (s >= 1) a.on = false;
  }
  // Slew: the slowest limit among a target's bindings (0 = none).
  for (size_t h = 0; h < goal_.size(); ++h) {
    double slew = 0;
    for (const Binding& b : bindings_)
      if (b.tf.slew > 0 && b.index == int(h) &&
          (b.target == TargetKind::HandleX || b.target == TargetKind::HandleY || b.target == TargetKind::HandlePoint))
        slew = slew > 0 ? std::min(slew, b.tf.slew) : b.tf.slew;
    const Vec2 d = goal_[h] - current_[h];
    const double n = d.norm(), max = slew * dt;
    current_[h] = (slew > 0 && n > max) ? Vec2(current_[h] + d * (max / n)) : goal_[h];
  }
  for (size_t g = 0; g < groups_.size(); ++g) {
    double slew = 0;
    for (const Binding& b : bindings_)
      if (b.tf.slew > 0 && b.target == TargetKind::Rotate && b.index == int(g))
        slew = slew > 0 ? std::min(slew, b.tf.slew) : b.tf.slew;
    const double d = angle_goal_[g] - angle_[g], max = slew * dt;
    angle_[g] = (slew > 0 && std::fabs(d) > max) ? angle_[g] + std::copysign(max, d) : angle_goal_[g];
  }
  for (size_t h = 0; h < current_.size(); ++h) targets_[h] = current_[h];
  for (size_t g = 0; g < groups_.size(); ++g) {
    const RotationGroup& grp = groups_[g];
    const Vec2 moved = grp.follow >= 0 ? Vec2(targets_[size_t(grp.follow)] - rest_[size_t(grp.follow)]) : Vec2::Zero();
    const Vec2 pivot = grp.pivot_handle >= 0 ? targets_[size_t(grp.pivot_handle)] : Vec2(grp.pivot + moved);
    pivots_[g] = pivot;
    const double c = std::cos(angle_[g] * kDeg), s = std::sin(angle_[g] * kDeg);
    for (int h : grp.handles) {
      const Vec2 r = targets_[size_t(h)] + moved - pivot;
      targets_[size_t(h)] = pivot + Vec2(c * r.x() - s * r.y(), s * r.x() + c * r.y());
    }
  }
}

}  // namespace mar
