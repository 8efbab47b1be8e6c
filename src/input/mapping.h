// Mapping: Events -> handle targets, rotations, poses and named settings. A setting is a
// number the loop or the solver reads (the show names them solver.iterations,
// solver.rigidity, ...); the mapping only keeps it within its range and says when it moved.
//
// A binding listens to one control of one device and drives one target through its
// transforms. Absolute controls: normalise by the control's range, deadzone (about the
// centre), invert, curve (exponent), One Euro filter, soft takeover, then scale to the
// target range. Relative controls (encoders, jog wheels, relative CCs in any encoding)
// add delta x step. Buttons (notes, GPIO and HID buttons, or a CC / HID value / OSC value
// crossing the binding's threshold): momentary (low/high of the range while held) or toggle.
// A pose target eases every handle it names to its position over the binding's transition
// (pose.KEY of a rig key asks the loop for the same along the key interpolation: take_recall);
// a swap target shows one member of a swap set (latched, or while held); a trigger shows its
// shapes while held (or toggles). A pointer dragging a handle may return it to rest on release,
// eased over `return` seconds. 14-bit CC pairs and NRPN assemble their value before the
// transforms. Slew limits act per frame on the final targets.
//
// All state is sized when the show loads; apply() and update() allocate nothing.
#pragma once

#include "geom/types.h"
#include "input/arbitration.h"
#include "input/event.h"
#include "input/filters.h"
#include "input/hid_usages.h"

#include <functional>
#include <span>
#include <string>
#include <vector>

namespace mar {

struct ControlSpec {
  /// NoteVelocity: a note's velocity while held, 0 after its note-off; Aftertouch: channel
  /// pressure; PolyPressure: a note's own pressure (continuous controls, 0..127).
  /// Beat, Bar: MIDI clock's phase within the beat and the bar, 0..1 (input/midi_clock.h).
  enum Kind : uint8_t { CC, CC14, NRPN, Note, PitchBend, Hid, Encoder, GpioButton, Pointer, NoteVelocity, Aftertouch, PolyPressure, Beat, Bar } kind = CC;
  uint16_t device = 0;
  int channel = -1;     ///< MIDI channel 0-15, -1 = any
  uint32_t number = 0;  ///< CC / note / NRPN parameter / HID usage / encoder or button index
  /// HID usages of a pointer: x, y, tip (defaults: Generic Desktop X/Y, Digitizer Tip Switch)
  uint32_t px = usage::kX, py = usage::kY, ptip = usage::kTipSwitch, ppressure = usage::kTipPressure;
  std::string text;     ///< as written (for messages and learn)
};

enum class TargetKind : uint8_t { HandleX, HandleY, HandlePoint, Rotate, Setting, Pose, Grab, Swap, Trigger, Recall, Brush, Curve };

/// Targets a control presses rather than sets (a CC or HID value presses past the threshold).
inline bool button_target(TargetKind k) {
  return k == TargetKind::Pose || k == TargetKind::Swap || k == TargetKind::Trigger || k == TargetKind::Recall;
}

/// Easing of a timed transition, s in [0, 1] -> [0, 1].
enum class Ease : uint8_t { Linear, In, Out, InOut };
double ease(Ease e, double s);

/// A named number a binding may drive (its meaning belongs to whoever reads it).
struct Setting {
  double value = 0, lo = 0, hi = 1;
  bool integer = false;  ///< rounded; stepped, so absolute controls set it without soft takeover
};

struct Transform {
  double lo = 0, hi = 1;       ///< output range (target units; degrees for rotations)
  bool has_range = false;
  double curve = 1;            ///< exponent applied to the normalised value
  bool invert = false;
  double deadzone = 0;         ///< fraction of the half range about the centre
  OneEuro one_euro;
  double slew = 0;             ///< max target speed, units per second (0 = off)
  bool takeover = true;        ///< soft takeover for absolute controls
  RelativeMode relative = RelativeMode::Absolute;
  double step = 1;             ///< units per relative tick
  bool toggle = false;         ///< buttons: toggle (latch) instead of momentary
  double threshold = 0.5;      ///< a CC / HID / OSC value presses a button target from here (0..1)
  double transition = 0.3;     ///< pose targets: seconds to reach the pose (0: jump)
  Ease ease = Ease::InOut;
  double ret = -1;             ///< pointer on a handle: seconds back to rest on release (< 0: hold)
  double area[4] = {0, 0, 1, 1};  ///< pointer: target rectangle x0 y0 x1 y1
  /// Pointer over the canvas (`area = "canvas"`, a cast's default): `canvas_map` takes its
  /// normalised position to target units (a b c d e f, as Affine2: through the character's view).
  bool area_canvas = false;
  double canvas_map[6] = {1, 0, 0, 1, 0, 0};
  /// Priority among the bindings on its target (input/arbitration.h): stated (here or by its
  /// device) puts every binding on that handle axis, rotation or setting under arbitration,
  /// which replaces soft takeover there.
  SourcePriority priority;
  bool has_priority = false;
};

struct Binding {
  ControlSpec control;
  TargetKind target = TargetKind::HandleX;
  int index = 0;  ///< handle, group, pose, setting, swap set, trigger or key (-1: rest) index
  int member = 0; ///< swap targets: the member shown; a recall's: the cast's character
  Transform tf;
  int line = 0;   ///< show-file line (messages)
  std::string target_text;  ///< as written (the HUD)
  int led = -1;              ///< its control's light when lit: -1 the profile's, -2 none (app/loop/leds.h)
  // state
  bool engaged = false;      ///< soft takeover has picked the target up
  uint8_t takeover_told = 0; ///< 1: it has waited for soft takeover, not yet said; 2: said (or picked up)
  int64_t takeover_since = 0; ///< the event time of its first wait
  double last_norm = -1;     ///< previous normalised control value (-1: none yet)
  bool toggled = false, pressed = false;
  int before = 0;            ///< momentary swap: the member shown before the press
  int msb = 0, lsb = 0;      ///< 14-bit parts
  int nrpn_hi = 0, nrpn_param = -1;  ///< NRPN parameter selected by CC 99/98
  double px = 0.5, py = 0.5; ///< pointer position (normalised)
  double pressure = 1;       ///< pointer pressure (normalised; 1 until the pen reports one)
  bool tip = false;
  uint64_t hits = 0;         ///< events it has used (an idle behaviour on its target pauses)
  int arb = -1, arb_source = -1;  ///< its target's arbiter and its source there (-1: none)
};

struct RotationGroup {
  std::string name;
  std::vector<int> handles;
  Vec2 pivot = Vec2::Zero();
  int pivot_handle = -1;  ///< rotate about this handle's current target instead
  /// The group goes where this handle goes (-1: nowhere): its handles and its pivot move by
  /// that handle's target's offset from its rest (as the groups before this one left it) before
  /// they turn, so an arm turned by a knob swings about a shoulder the body's fader has moved.
  /// Not with pivot_handle, and not one of its own handles.
  int follow = -1;
};

struct Pose {
  std::string name;
  std::vector<Vec2> positions;  ///< per handle; NaN = leave alone
};

/// A pose recall along the key interpolation, asked by a pose.KEY binding.
struct Recall {
  int key = -1;  ///< rig key index, -1: rest
  double seconds = 0;
  Ease ease = Ease::InOut;
  int who = 0;   ///< the cast's character (0: a show's single rig)
};

struct MappingStats {
  uint64_t events = 0, matched = 0, takeover_waits = 0;
};

class Mapping {
 public:
  void set_handles(std::vector<std::string> names, std::vector<Vec2> rest);
  const std::vector<std::string>& handle_names() const { return names_; }
  int handle_index(const std::string& name) const;
  int add_group(RotationGroup g);
  int group_index(const std::string& name) const;
  int add_pose(Pose p);
  int pose_index(const std::string& name) const;
  void add_binding(Binding b);
  std::vector<Binding>& bindings() { return bindings_; }
  /// Adds a setting; returns its index.
  int add_setting(Setting s);
  /// Swap sets (member count, shown member) and triggers, in the rig's order.
  void set_swaps(std::vector<int> member_counts, std::vector<int> defaults, size_t triggers);
  /// A trigger's state as the show starts (a cast's NAME.on-stage: on when it is shown).
  void set_trigger(size_t t, bool on) { trigger_on_[t] = on ? 1 : 0; }
  int swap_member(size_t set) const { return swap_now_[set]; }
  bool trigger_on(size_t t) const { return trigger_on_[t] != 0; }
  /// Whether a swap or trigger changed since the last call.
  bool take_shown_changed() { bool c = shown_changed_; shown_changed_ = false; return c; }
  /// The latest pose recall asked for since the last call, if any.
  bool take_recall(Recall& out) {
    if (!recall_pending_) return false;
    recall_pending_ = false;
    out = recall_;
    return true;
  }
  /// Whether a binding has waited for soft takeover for the first time since the last call
  /// (its takeover_told is 1 until the caller says so and sets it to 2).
  bool take_takeover_news() { bool c = takeover_news_; takeover_news_ = false; return c; }
  /// The [[pose]] last pressed while no other control has moved a handle it places (-1: none).
  int current_pose() const { return current_pose_; }
  /// Whether handle h is easing toward a pose or back to rest.
  bool easing(int handle) const { return anim_[size_t(handle)].on; }

  /// A reloaded show's mapping (after its handles, groups and bindings are added) takes over
  /// from the running one: handles and groups by name where they were, and bindings of the same
  /// control what they knew of it; an absolute control that had picked its target up sets it
  /// now with its new range.
  void carry_from(const Mapping& old);
  /// Updates goals from one event. Returns true when some binding used it.
  bool apply(const Event& e);
  /// Advances slew-limited targets by `dt_s` and recomputes the final handle targets.
  void update(double dt_s);

  std::span<const Vec2> targets() const { return targets_; }
  /// Each group's pivot as the last targets turned about it (a follow moves it).
  std::span<const Vec2> pivots() const { return pivots_; }
  Vec2 goal(int handle) const { return goal_[size_t(handle)]; }
  double angle(int group) const { return angle_[size_t(group)]; }
  double setting(int i) const { return settings_[size_t(i)].value; }
  size_t setting_count() const { return settings_.size(); }
  /// Whether any setting changed since the last call.
  bool take_settings_changed() { bool c = settings_changed_; settings_changed_ = false; return c; }
  /// Grab-and-drag: a pointer with its tip down (position in character units).
  bool grab_active() const { return grab_active_; }
  /// The cast's character the pen grabs (a grab binding's index; 0: a show's single rig). One
  /// pen holds at a time: another's tip going down takes over; the holder's coming up lets go.
  int grab_who() const { return grab_who_; }
  Vec2 grab_point() const { return grab_point_; }
  /// The brush or the drawn curve (a [[brush]]'s or a [[curve]]'s pointer, app/loop/brush.h,
  /// curve.h): one pen sculpts at a time, as one grabs.
  struct Pen {
    bool down = false;
    bool curve = false;         ///< a [[curve]]'s (else a [[brush]]'s)
    Vec2 point = Vec2::Zero();  ///< character units
    double pressure = 1;
    int who = 0;                ///< the cast's character
    int brush = 0;              ///< which [[brush]] or [[curve]] (ShowConfig::brushes, curves)
  };
  const Pen& brush() const { return brush_; }
  /// Whether the cast's character `who` is drawn at `p` (its units): set by the stage, so that
  /// one pen with tools on several characters takes, as its tip goes down, the one whose
  /// character is under it (unset: the last of its tools, as any pointer takes over).
  void set_pen_hit(std::function<bool(int who, const Vec2& p)> hit) { pen_hit_ = std::move(hit); }
  const MappingStats& stats() const { return stats_; }
  // For the HUD: each binding, the value its target has now (NaN for targets without one:
  // grabs, poses, swaps, triggers, recalls), and where an absolute control waiting for soft
  // takeover must go to pick its target up (0..1 of its travel; -1 when not waiting).
  size_t binding_count() const { return bindings_.size(); }
  const Binding& binding(size_t i) const { return bindings_[i]; }
  double binding_value(size_t i) const;
  double takeover_at(size_t i) const;
  /// Under arbitration: 1 when binding i holds its target, 0 when it waits; -1 otherwise.
  int holds(size_t i) const;
  /// Binding i's target's arbiter (nullptr: not arbitrated).
  const Arbiter* arbiter(size_t i) const {
    return bindings_[i].arb >= 0 ? &arbs_[size_t(bindings_[i].arb)].arb : nullptr;
  }

 private:
  void absolute(Binding& b, double norm, int64_t t);
  void fourteen_bit(Binding& b, bool msb, int value, int64_t t);
  void relative(Binding& b, double delta);
  void button(Binding& b, bool down);
  void set_target(Binding& b, double value);
  double current_norm(const Binding& b) const;
  void written_by(const Binding* b, TargetKind k, int index);
  void ease_handle(int h, const Vec2& to, double seconds, Ease e);
  static bool arbitrable(TargetKind k) {
    return k == TargetKind::HandleX || k == TargetKind::HandleY || k == TargetKind::Rotate || k == TargetKind::Setting;
  }
  double raw(TargetKind k, int index) const;
  void put(TargetKind k, int index, double v);
  void arbitrated(Binding& b, double v);

  /// A target several bindings drive under priorities: its arbiter and its sources' bindings.
  struct ArbTarget {
    TargetKind kind = TargetKind::HandleX;
    int index = 0;
    Arbiter arb;
    std::vector<int> bindings;
  };
  std::vector<ArbTarget> arbs_;
  double clock_ = 0;  ///< seconds of update() so far: the arbiters' clock

  std::vector<std::string> names_;
  std::vector<Vec2> rest_, goal_, current_, targets_;
  std::vector<double> angle_goal_, angle_;
  std::vector<RotationGroup> groups_;
  std::vector<Vec2> pivots_;  // per group, where it turned last (sized with the groups)
  std::vector<Pose> poses_;
  std::vector<Binding> bindings_;
  int current_pose_ = -1;
  bool takeover_news_ = false;
  void put_setting(size_t i, double v);
  std::vector<Setting> settings_;
  bool settings_changed_ = false;
  struct Anim {
    bool on = false;
    Vec2 from = Vec2::Zero(), to = Vec2::Zero();
    double t = 0, seconds = 0;
    Ease ease = Ease::InOut;
  };
  std::vector<Anim> anim_;  ///< per handle
  std::vector<int> swap_now_, swap_count_;
  std::vector<char> trigger_on_;
  bool shown_changed_ = false;
  Recall recall_;
  bool recall_pending_ = false;
  bool grab_active_ = false;
  Vec2 grab_point_ = Vec2::Zero();
  Pen brush_;
  int brush_by_ = -1;  ///< the binding holding the brush (-1: none)
  bool brush_hit_ = false;  ///< its character was under the pen when its tip went down
  std::function<bool(int, const Vec2&)> pen_hit_;
  int grab_who_ = 0;
  int grab_by_ = -1;  ///< the grab binding whose pen holds (-1: none)
  MappingStats stats_;
};

}  // namespace mar
