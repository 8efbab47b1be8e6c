#include "app/show.h"
#include "firmware_sim/midi_controller.h"
#include "app/show_toml.h"
#include "character/color.h"
#include "input/hid_usages.h"
#include "rig/edit.h"

#include <SDL2/SDL.h>
#include <toml++/toml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace mar {
namespace {

using namespace showtoml;

toml::table parse_file(const std::string& path) {
  Result<std::string> file_text = read_file(path, kMaxTomlBytes, "a show file");
  if (!file_text.ok()) throw ShowError{file_text.error};
  Result<toml::table> t = cfg::parse_toml(*file_text.value, path);
  if (!t.ok()) throw ShowError{t.error};
  return std::move(*t.value);
}

void read_header(const std::string& path, const toml::table& root, ShowConfig& s) {
  check_keys(path, root, {"show", "display", "output", "kiosk", "attract", "device", "binding", "group", "pose", "physics", "behavior", "osc_out",
                          "scenery", "prop", "character", "brush", "curve"}, "the show file");
  const toml::node* sn = root.get("show");
  if (!sn || !sn->is_table()) throw ShowError{path + ":1: missing [show] table (character, rig, rate)"};
  const toml::table& t = *sn->as_table();
  check_keys(path, t, {"character", "rig", "rate", "iterations", "min_iterations", "late_input", "late_input_margin_ms", "images", "threads"},
             "[show]");
  if (auto* n = t.get("images")) {
    const std::string v = text(path, *n, "images");
    if (v != "beside" && v != "anywhere")
      throw ShowError{at(path, *n) + ": images must be \"beside\" (the character's folder and below) or \"anywhere\""};
    s.images_anywhere = v == "anywhere";
  }
  if (auto* n = t.get("character")) s.character = resolve(path, text(path, *n, "character"));
  if (auto* n = t.get("rig")) s.rig = resolve(path, text(path, *n, "rig"));
  else if (!root.get("character")) throw ShowError{at(path, *sn) + ": [show] needs a rig (or the show a cast: [[character]] tables)"};
  if (s.rig.empty() && root.get("character") && t.get("character"))
    throw ShowError{at(path, *t.get("character")) + ": [show] character goes with [show] rig; a cast's characters are [[character]] tables"};
  if (auto* n = t.get("rate")) {
    s.rate_hz = number(path, *n, "rate");
    if (s.rate_hz < 1 || s.rate_hz > 1000) throw ShowError{at(path, *n) + ": rate must be 1..1000 Hz"};
  }
  if (auto* n = t.get("iterations")) {
    s.iterations = integer(path, *n, "iterations", 1, 200);
  }
  if (auto* n = t.get("min_iterations")) {
    s.min_iterations = integer(path, *n, "min_iterations", 1, 200);
    if (s.min_iterations > s.iterations)
      throw ShowError{at(path, *n) + ": min_iterations must be 1..iterations"};
  }
  s.min_iterations = std::min(s.min_iterations, s.iterations);
  if (auto* n = t.get("late_input")) s.late_input = boolean(path, *n, "late_input");
  if (auto* n = t.get("threads")) s.threads = integer(path, *n, "threads", 1, 64);
  if (auto* n = t.get("late_input_margin_ms")) {
    s.late_input_margin_ms = number(path, *n, "late_input_margin_ms");
    if (!(s.late_input_margin_ms >= 0 && s.late_input_margin_ms <= 100))
      throw ShowError{at(path, *n) + ": late_input_margin_ms must be 0..100"};
  }
  if (const toml::node* dn = root.get("display")) {
    const toml::table* d = dn->as_table();
    if (!d) throw ShowError{at(path, *dn) + ": [display] must be a table"};
    check_keys(path, *d, {"width", "height", "fullscreen", "hud", "background", "screen", "vsync"}, "[display]");
    if (auto* n = d->get("width")) s.width = integer(path, *n, "width", 16, 8192);
    if (auto* n = d->get("height")) s.height = integer(path, *n, "height", 16, 8192);
    if (s.width < 16 || s.height < 16 || s.width > 8192 || s.height > 8192)
      throw ShowError{at(path, *dn) + ": display size must be 16..8192"};
    if (auto* n = d->get("fullscreen")) s.fullscreen = boolean(path, *n, "fullscreen");
    if (auto* n = d->get("vsync")) s.vsync = boolean(path, *n, "vsync");
    if (auto* n = d->get("hud")) s.hud = boolean(path, *n, "hud");
    if (auto* n = d->get("background")) {
      s.background = text(path, *n, "background");
      if (!parse_background_color(s.background))
        throw ShowError{at(path, *n) + ": background must be a colour (\"#f4f1ea\", \"white\"), \"transparent\" or "
                                        "\"chroma-green\", \"chroma-blue\", \"chroma-magenta\"; got '" + s.background + "'"};
    }
    if (auto* n = d->get("screen")) {
      if (n->is_string()) s.screen_name = text(path, *n, "screen");
      else s.screen = integer(path, *n, "screen", 0, 15);
    }
  }
  if (const toml::node* on = root.get("output")) {
    const toml::table* o = on->as_table();
    if (!o) throw ShowError{at(path, *on) + ": [output] must be a table"};
    check_keys(path, *o, {"width", "height", "pipewire"}, "[output]");
    if (auto* n = o->get("pipewire")) s.out_pipewire = boolean(path, *n, "pipewire");
    if (auto* n = o->get("width")) s.out_width = integer(path, *n, "width", 16, 8192);
    if (auto* n = o->get("height")) s.out_height = integer(path, *n, "height", 16, 8192);
    if ((s.out_width > 0) != (s.out_height > 0)) throw ShowError{at(path, *on) + ": [output] needs both width and height"};
  }
  if (const toml::node* on = root.get("osc_out")) {
    const toml::table* o = on->as_table();
    if (!o) throw ShowError{at(path, *on) + ": [osc_out] must be a table"};
    check_keys(path, *o, {"host", "port", "rate", "prefix"}, "[osc_out]");
    const toml::node* port = o->get("port");
    if (!port) throw ShowError{at(path, *on) + ": [osc_out] needs a port (where to send)"};
    s.osc_out.port = integer(path, *port, "port", 1, 65535);
    if (auto* n = o->get("host")) s.osc_out.host = text(path, *n, "host");
    if (auto* n = o->get("rate")) {
      s.osc_out.rate = number(path, *n, "rate");
      if (!(s.osc_out.rate >= 1 && s.osc_out.rate <= 1000)) throw ShowError{at(path, *n) + ": [osc_out] rate must be 1..1000 sends a second"};
    }
    if (auto* n = o->get("prefix")) {
      s.osc_out.prefix = text(path, *n, "prefix");
      if (s.osc_out.prefix.empty() || s.osc_out.prefix[0] != '/' || s.osc_out.prefix.find_first_of(" #*,?[]{}") != std::string::npos)
        throw ShowError{at(path, *n) + ": [osc_out] prefix must be an OSC address such as \"/marionette\""};
    }
  }
  if (const toml::node* kn = root.get("kiosk")) {
    const toml::table* k = kn->as_table();
    if (!k) throw ShowError{at(path, *kn) + ": [kiosk] must be a table"};
    check_keys(path, *k, {"enabled", "display", "exit_chord"}, "[kiosk]");
    s.kiosk.enabled = true;
    if (auto* n = k->get("enabled")) s.kiosk.enabled = boolean(path, *n, "enabled");
    if (auto* n = k->get("display")) s.kiosk.display = integer(path, *n, "display", 0, 15);
    if (auto* n = k->get("exit_chord")) {
      s.kiosk.exit_chord = text(path, *n, "exit_chord");
      if (auto r = parse_chord(s.kiosk.exit_chord, s.kiosk.key, s.kiosk.mod); !r.ok()) throw ShowError{at(path, *n) + ": " + r.error};
    }
  }
}

// [[device]]: simulators and hardware (read_hardware, show_devices.cpp).
void read_devices(const std::string& path, const toml::table& root, ShowConfig& s) {
  if (const toml::array* devs = array_of_tables(path, root, "device")) {
    for (const toml::node& dn : *devs) {
      const toml::table& t = *dn.as_table();
      check_device_keys(path, t);
      ShowDevice d;
      d.line = int(dn.source().begin.line);
      const toml::node* name = t.get("name");
      if (!name) throw ShowError{at(path, dn) + ": [[device]] needs a name"};
      d.name = text(path, *name, "name");
      for (const auto& other : s.devices)
        if (other.name == d.name) throw ShowError{at(path, *name) + ": device '" + d.name + "' is named twice"};
      if (auto* n = t.get("type")) d.type = text(path, *n, "type");
      read_hardware(path, t, d);  // type, identity, profile (show_devices.cpp)
      if (const toml::node* sim = t.get("sim")) {
        d.sim = text(path, *sim, "sim");
        if (!midi_model(d.sim) && d.sim != "knob_box" && d.sim != "pen_tablet" && d.sim != "gamepad" && d.sim != "microphone")
          throw ShowError{at(path, *sim) + ": unknown simulated device '" + d.sim + "' (" + midi_model_names() +
                          ", knob_box, pen_tablet, gamepad, microphone)"};
      } else if (d.type == "sim" && d.sim.empty()) {  // (a profile names its simulator)
        throw ShowError{at(path, dn) + ": a sim device needs sim = " + midi_model_names() + ", knob_box, pen_tablet, gamepad or microphone"};
      }
      if (d.sim == "microphone" || d.type == "audio") read_voice(path, t, d);  // show_devices.cpp: file, pcm, calibrate, names
      if (auto* n = t.get("descriptor")) {
        const std::string desc = text(path, *n, "descriptor");
        d.descriptor = resolve(path, desc);
        d.descriptor_in_corpus = desc.rfind("corpus:", 0) == 0;
      }
      if (auto* n = t.get("script")) d.script = text(path, *n, "script");
      if (auto* n = t.get("script_file")) d.script = read_script_file(path, *n);
      auto millis = [&](const toml::node& n, const char* what) {  // 0..10 s (ns fit an int64)
        const double v = number(path, n, what);
        if (v < 0 || v > 10000) throw ShowError{at(path, n) + ": " + what + " must be 0..10000 ms"};
        return v;
      };
      if (auto* n = t.get("bounce_ms")) d.bounce_ms = millis(*n, "bounce_ms");
      if (auto* n = t.get("debounce_ms")) d.debounce_ms = millis(*n, "debounce_ms");
      if (auto* n = t.get("seed")) d.seed = uint32_t(integer(path, *n, "seed", 0, 2147483647));
      if (auto* n = t.get("priority")) {
        d.priority = int(integer(path, *n, "priority", -1000, 1000));
        d.has_priority = true;
      }
      s.devices.push_back(std::move(d));
    }
  }
}

// One [[binding]]: its device and control, its target (resolved against the rig), its
// transforms, its light and its priority.
Binding read_binding(const std::string& path, const toml::node& bn, ShowConfig& s, const ShowRig& rig) {
  const std::vector<Vec2>& rest = rig.rest;
  const toml::table& t = *bn.as_table();
  check_keys(path, t, {"device", "control", "target", "range", "curve", "invert", "deadzone", "filter", "slew",
                       "takeover", "mode", "step", "button", "area", "threshold", "transition", "ease", "return", "led",
                       "priority", "hold", "handover"},
             "[[binding]]");
  Binding b;
  b.line = int(bn.source().begin.line);
  const toml::node* dev = t.get("device");
  const toml::node* ctl = t.get("control");
  const toml::node* tgt = t.get("target");
  if (!dev || !ctl || !tgt) throw ShowError{at(path, bn) + ": [[binding]] needs device, control and target"};
  const int di = device_named(path, *dev, s);
  b.control.device = uint16_t(di);
  const std::string written = text(path, *ctl, "control");
  if (auto r = parse_control(device_control(s.devices[size_t(di)], written), b.control); !r.ok())
    throw ShowError{at(path, *ctl) + ": " + r.error};
  b.control.text = written;  // as the show names it ("pad_r1c1", "fader1"): the HUD and messages say that
  b.target_text = text(path, *tgt, "target");
  if (auto r = parse_target(b.target_text, s, rig, b.target, b.index, &b.member); !r.ok())
    throw ShowError{at(path, *tgt) + ": " + r.error};
  if (const toml::node* led = t.get("led")) read_binding_led(path, *led, s.devices[size_t(di)], b);  // show_devices.cpp
  Transform& tf = b.tf;
  // Default ranges: a handle axis moves +-1/4 of the character's diagonal about its
  // rest position; a rotation turns -90..90 degrees.
  if (b.target == TargetKind::HandleX || b.target == TargetKind::HandleY) {
    const double c = b.target == TargetKind::HandleX ? rest[size_t(b.index)].x() : rest[size_t(b.index)].y();
    tf.lo = c - 0.25 * rig.diag_of(b.index);
    tf.hi = c + 0.25 * rig.diag_of(b.index);
  } else if (b.target == TargetKind::Rotate) {
    tf.lo = -90;
    tf.hi = 90;
  } else if (b.target == TargetKind::Setting && rig.settings[size_t(b.index)].default_range) {
    std::tie(tf.lo, tf.hi) = *rig.settings[size_t(b.index)].default_range;
  }
  if (auto* n = t.get("range")) {
    std::tie(tf.lo, tf.hi) = pair_of(path, *n, "range");
    tf.has_range = true;
  }
  if (auto* n = t.get("curve")) {
    tf.curve = number(path, *n, "curve");
    if (tf.curve <= 0) throw ShowError{at(path, *n) + ": curve must be > 0"};
  }
  if (auto* n = t.get("invert")) tf.invert = boolean(path, *n, "invert");
  if (auto* n = t.get("deadzone")) {
    tf.deadzone = number(path, *n, "deadzone");
    if (tf.deadzone < 0 || tf.deadzone >= 1) throw ShowError{at(path, *n) + ": deadzone must be 0..1"};
  }
  if (auto* n = t.get("filter")) {
    const toml::table* f = n->as_table();
    if (!f) throw ShowError{at(path, *n) + ": filter must be { min_cutoff, beta, d_cutoff }"};
    check_keys(path, *f, {"min_cutoff", "beta", "d_cutoff"}, "filter");
    tf.one_euro.enabled = true;
    if (auto* x = f->get("min_cutoff")) tf.one_euro.min_cutoff = number(path, *x, "min_cutoff");
    if (auto* x = f->get("beta")) tf.one_euro.beta = number(path, *x, "beta");
    if (auto* x = f->get("d_cutoff")) tf.one_euro.d_cutoff = number(path, *x, "d_cutoff");
    if (tf.one_euro.min_cutoff <= 0 || tf.one_euro.d_cutoff <= 0 || tf.one_euro.beta < 0)
      throw ShowError{at(path, *n) + ": filter cutoffs must be > 0 and beta >= 0"};
  }
  if (auto* n = t.get("slew")) tf.slew = std::max(0.0, number(path, *n, "slew"));
  // Soft takeover by default for what a hand moves through its travel; controls that can
  // only jump (an OSC value, a note or a button, a velocity, the clock's phase) would wait
  // for ever, so they set their target at once unless the show says otherwise.
  const ControlSpec& cs = b.control;
  if (cs.kind == ControlSpec::Note || cs.kind == ControlSpec::GpioButton || cs.kind == ControlSpec::NoteVelocity ||
      cs.kind == ControlSpec::Beat || cs.kind == ControlSpec::Bar ||
      (cs.kind == ControlSpec::Hid && (cs.number & 0xFF000000u) == 0xFF000000u))
    tf.takeover = false;
  if (auto* n = t.get("takeover")) tf.takeover = boolean(path, *n, "takeover");
  if (auto* n = t.get("mode")) {
    const std::string m = text(path, *n, "mode");
    static const std::pair<const char*, RelativeMode> modes[] = {
        {"absolute", RelativeMode::Absolute}, {"twos_complement", RelativeMode::TwosComplement},
        {"binary_offset", RelativeMode::BinaryOffset}, {"sign_magnitude", RelativeMode::SignMagnitude},
        {"sign_magnitude_inverted", RelativeMode::SignMagnitudeInv}, {"delta", RelativeMode::Delta}};
    bool ok = false;
    for (auto [name, mode] : modes)
      if (m == name) {
        tf.relative = mode;
        ok = true;
      }
    if (!ok)
      throw ShowError{at(path, *n) + ": mode must be absolute, twos_complement, binary_offset, "
                                     "sign_magnitude, sign_magnitude_inverted or delta"};
  }
  if (auto* n = t.get("step")) tf.step = number(path, *n, "step");
  tf.toggle = b.target == TargetKind::Swap;  // a pad picks a member and it stays
  if (auto* n = t.get("button")) {
    const std::string m = text(path, *n, "button");
    if (m != "momentary" && m != "toggle" && m != "latch")
      throw ShowError{at(path, *n) + ": button must be momentary, toggle or latch"};
    tf.toggle = m != "momentary";
  }
  if (auto* n = t.get("threshold")) {
    tf.threshold = number(path, *n, "threshold");
    if (!(tf.threshold > 0 && tf.threshold <= 1))
      throw ShowError{at(path, *n) + ": threshold must be in (0, 1] (the fraction of the control's range that presses)"};
  }
  if (auto* n = t.get("transition")) {
    if (b.target != TargetKind::Pose && b.target != TargetKind::Recall)
      throw ShowError{at(path, *n) + ": transition goes with a pose.NAME target"};
    tf.transition = number(path, *n, "transition");
    if (!(tf.transition >= 0 && tf.transition <= 60)) throw ShowError{at(path, *n) + ": transition must be 0..60 seconds"};
  }
  if (auto* n = t.get("ease")) {
    const std::string e = text(path, *n, "ease");
    static const std::pair<const char*, Ease> eases[] = {
        {"linear", Ease::Linear}, {"in", Ease::In}, {"out", Ease::Out}, {"in_out", Ease::InOut}};
    bool ok = false;
    for (auto [name, ea] : eases)
      if (e == name) tf.ease = ea, ok = true;
    if (!ok) throw ShowError{at(path, *n) + ": ease must be linear, in, out or in_out"};
  }
  if (auto* n = t.get("return")) {
    if (b.control.kind != ControlSpec::Pointer || b.target != TargetKind::HandlePoint)
      throw ShowError{at(path, *n) + ": return goes with a pointer dragging a handle (target handle.NAME)"};
    if (n->is_string() && *n->value<std::string>() == "hold") {
      tf.ret = -1;
    } else {
      tf.ret = number(path, *n, "return");
      if (!(tf.ret >= 0 && tf.ret <= 60)) throw ShowError{at(path, *n) + ": return must be 0..60 seconds or \"hold\""};
    }
  }
  if (auto* n = t.get("area")) {
    const toml::array* a = n->as_array();
    if (n->is_string() && *n->value<std::string>() == "canvas") {
      tf.area_canvas = true;
    } else if (!a || a->size() != 4) {
      throw ShowError{at(path, *n) + ": area must be [x0, y0, x1, y1] (character units) or \"canvas\""};
    }
    for (size_t i = 0; i < 4 && a; ++i) tf.area[i] = number(path, *a->get(i), "area");
  }
  read_priority(path, t, s.devices[size_t(di)], b);
  return b;
}

}  // namespace

std::string format_control(const ControlSpec& c) {
  std::string out;
  switch (c.kind) {
    case ControlSpec::CC: out = "cc " + std::to_string(c.number); break;
    case ControlSpec::CC14: out = "cc14 " + std::to_string(c.number); break;
    case ControlSpec::NRPN: out = "nrpn " + std::to_string(c.number); break;
    case ControlSpec::Note: out = "note " + std::to_string(c.number); break;
    case ControlSpec::PitchBend: out = "pitchbend"; break;
    case ControlSpec::NoteVelocity: out = "note " + std::to_string(c.number) + " velocity"; break;
    case ControlSpec::Aftertouch: out = "aftertouch"; break;
    case ControlSpec::PolyPressure: out = "polypressure " + std::to_string(c.number); break;
    case ControlSpec::Beat: out = "beat"; break;
    case ControlSpec::Bar: out = "bar"; break;
    case ControlSpec::Encoder: out = "encoder " + std::to_string(c.number); break;
    case ControlSpec::GpioButton: out = "button " + std::to_string(c.number); break;
    case ControlSpec::Pointer: out = "pointer"; break;
    case ControlSpec::Hid: {
      for (auto [n, u] : usage::kNames)
        if (u == c.number) out = std::string("usage ") + n;
      if (out.empty() && (c.number >> 16) == usage::kButtonPage && (c.number & 0xFFFF) > 0) {
        out = "usage button" + std::to_string(c.number & 0xFFFF);
      }
      if (out.empty()) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "usage 0x%06X", c.number);
        out = buf;
      }
      break;
    }
  }
  const bool midi = c.kind == ControlSpec::CC || c.kind == ControlSpec::CC14 || c.kind == ControlSpec::NRPN ||
                    c.kind == ControlSpec::Note || c.kind == ControlSpec::PitchBend || c.kind == ControlSpec::NoteVelocity ||
                    c.kind == ControlSpec::Aftertouch || c.kind == ControlSpec::PolyPressure;
  if (midi && c.channel >= 0) out += " ch " + std::to_string(c.channel + 1);
  return out;
}

Result<bool> parse_control(const std::string& s, ControlSpec& c) {
  using R = Result<bool>;
  std::istringstream in(s);
  std::vector<std::string> w;
  for (std::string t; in >> t;) w.push_back(t);
  c.text = s;
  if (w.empty()) return R::failure("empty control");
  auto num = [&](size_t i, uint32_t& out, uint32_t max) {
    if (i >= w.size()) return false;
    char* end = nullptr;
    const unsigned long v = std::strtoul(w[i].c_str(), &end, 0);
    if (*end || v > max) return false;
    out = uint32_t(v);
    return true;
  };
  size_t used = 1;
  if (w[0] == "cc" || w[0] == "cc14" || w[0] == "note" || w[0] == "nrpn") {
    c.kind = w[0] == "cc" ? ControlSpec::CC : w[0] == "cc14" ? ControlSpec::CC14 : w[0] == "note" ? ControlSpec::Note : ControlSpec::NRPN;
    const uint32_t max = c.kind == ControlSpec::NRPN ? 16383 : c.kind == ControlSpec::CC14 ? 31 : 127;
    if (!num(1, c.number, max)) return R::failure("'" + w[0] + "' needs a number 0.." + std::to_string(max));
    used = 2;
    if (c.kind == ControlSpec::Note && w.size() > 2 && w[2] == "velocity") {  // a continuous control
      c.kind = ControlSpec::NoteVelocity;
      used = 3;
    }
  } else if (w[0] == "polypressure") {
    c.kind = ControlSpec::PolyPressure;
    if (!num(1, c.number, 127)) return R::failure("'polypressure' needs a note number 0..127");
    used = 2;
  } else if (w[0] == "aftertouch") {
    c.kind = ControlSpec::Aftertouch;
  } else if (w[0] == "beat" || w[0] == "bar") {
    c.kind = w[0] == "beat" ? ControlSpec::Beat : ControlSpec::Bar;
  } else if (w[0] == "pitchbend") {
    c.kind = ControlSpec::PitchBend;
  } else if (w[0] == "encoder" || w[0] == "button") {
    c.kind = w[0] == "encoder" ? ControlSpec::Encoder : ControlSpec::GpioButton;
    if (!num(1, c.number, 255) || c.number < 1) return R::failure("'" + w[0] + "' needs an index from 1");
    used = 2;
  } else if (w[0] == "usage") {
    c.kind = ControlSpec::Hid;
    if (w.size() < 2) return R::failure("'usage' needs a name or number");
    bool found = false;
    for (auto [n, u] : usage::kNames)
      if (w[1] == n) {
        c.number = u;
        found = true;
      }
    if (!found && w[1].rfind("button", 0) == 0) {
      uint32_t b = 0;
      w.push_back(w[1].substr(6));
      if (num(w.size() - 1, b, 0xFFFF) && b > 0) {
        c.number = usage::button(b);
        found = true;
      }
      w.pop_back();
    }
    if (!found && !num(1, c.number, 0xFFFFFFFF))
      return R::failure("unknown usage '" + w[1] + "' (x, y, z, rx, ry, rz, dial, wheel, hat, pressure, tip, "
                        "in_range, barrel, x_tilt, y_tilt, buttonN, or a number page<<16|id)");
    used = 2;
  } else if (w[0] == "pointer") {
    c.kind = ControlSpec::Pointer;
  } else {
    return R::failure("unknown control '" + w[0] + "' (cc, cc14, nrpn, note, note N velocity, aftertouch, polypressure, pitchbend, beat, bar, usage, "
                      "encoder, button, pointer)");
  }
  if (used + 2 == w.size() && w[used] == "ch") {
    uint32_t ch = 0;
    if (!num(used + 1, ch, 16) || ch < 1) return R::failure("channel must be 1..16");
    c.channel = int(ch) - 1;
    used += 2;
  }
  if (used != w.size()) return R::failure("unexpected '" + w[used] + "' in control '" + s + "'");
  return R::success(true);
}

Result<bool> parse_target(const std::string& t, const ShowConfig& s, const ShowRig& rig, TargetKind& kind, int& index,
                          int* member) {
  using R = Result<bool>;
  auto find = [](const auto& list, const std::string& name) {
    for (size_t i = 0; i < list.size(); ++i)
      if (list[i] == name) return int(i);
    return -1;
  };
  if (!rig.cast.empty()) return parse_cast_target(t, s, rig, kind, index, member);  // show_cast.cpp
  if (t == "grab" || t == "brush" || t == "curve") {
    kind = t == "grab" ? TargetKind::Grab : t == "brush" ? TargetKind::Brush : TargetKind::Curve;
    index = 0;
    return R::success(true);
  }
  if (t.rfind("morph.", 0) == 0 || t.rfind("blend.", 0) == 0) {  // key poses (the rig's [[key]])
    std::string names;
    for (size_t i = 0; i < rig.settings.size(); ++i) {
      const std::string& n = rig.settings[i].name;
      if (n.rfind("morph.", 0) != 0 && n.rfind("blend.", 0) != 0) continue;
      if (n == t) {
        kind = TargetKind::Setting;
        index = int(i);
        return R::success(true);
      }
      if (n.rfind("blend.", 0) == 0) names += (names.empty() ? "" : ", ") + n;
    }
    if (names.empty()) return R::failure("'" + t + "': the rig has no key poses ([[key]]) on the feature frame");
    return R::failure("unknown key target '" + t + "' (morph.FROM.TO with FROM, TO among rest and the keys; " + names + ")");
  }
  if (t.rfind("solver.", 0) == 0) {
    std::string names;
    for (size_t i = 0; i < rig.settings.size(); ++i) {
      if (rig.settings[i].name.rfind("morph.", 0) == 0 || rig.settings[i].name.rfind("blend.", 0) == 0 ||
          rig.settings[i].name.rfind("physics.", 0) == 0)
        continue;
      if ("solver." + rig.settings[i].name == t) {
        kind = TargetKind::Setting;
        index = int(i);
        return R::success(true);
      }
      names += (i ? ", solver." : "solver.") + rig.settings[i].name;
    }
    return R::failure("unknown setting '" + t + "' (this rig's solver offers " + names + ")");
  }
  if (t.rfind("physics.", 0) == 0) {  // secondary motion (the rig's [[physics]] chains)
    std::string names;
    for (size_t i = 0; i < rig.settings.size(); ++i) {
      if (rig.settings[i].name.rfind("physics.", 0) != 0) continue;
      if (rig.settings[i].name == t) {
        kind = TargetKind::Setting;
        index = int(i);
        return R::success(true);
      }
      names += (names.empty() ? "" : ", ") + rig.settings[i].name;
    }
    if (names.empty()) return R::failure("'" + t + "': the rig has no [[physics]] chains");
    return R::failure("unknown physics setting '" + t + "' (" + names + ")");
  }
  const auto dot = t.find('.');
  const std::string head = t.substr(0, dot), rest = dot == std::string::npos ? "" : t.substr(dot + 1);
  if (head == "handle") {
    std::string name = rest;
    kind = TargetKind::HandlePoint;
    if (name.size() > 2 && (name.ends_with(".x") || name.ends_with(".y"))) {
      kind = name.back() == 'x' ? TargetKind::HandleX : TargetKind::HandleY;
      name.resize(name.size() - 2);
    }
    index = find(rig.handles, name);
    if (index < 0) return R::failure("the rig has no handle '" + name + "'");
    return R::success(true);
  }
  if (head == "rotate") {
    kind = TargetKind::Rotate;
    index = -1;
    for (size_t i = 0; i < s.groups.size(); ++i)
      if (s.groups[i].name == rest) index = int(i);
    if (index < 0) return R::failure("no [[group]] named '" + rest + "'");
    return R::success(true);
  }
  if (head == "pose") {
    kind = TargetKind::Pose;
    index = -1;
    for (size_t i = 0; i < s.poses.size(); ++i)
      if (s.poses[i].name == rest) index = int(i);
    if (index >= 0) return R::success(true);
    kind = TargetKind::Recall;  // a rig key (or rest), along the interpolation
    if (!rig.keys.empty() && rest == "rest") {
      index = -1;
      return R::success(true);
    }
    index = find(rig.keys, rest);
    if (index >= 0) return R::success(true);
    std::string names;
    for (const Pose& p : s.poses) names += (names.empty() ? "" : ", ") + p.name;
    for (const std::string& k : rig.keys) names += (names.empty() ? "" : ", ") + k;
    return R::failure("no [[pose]] or rig key named '" + rest + "'" + (names.empty() ? std::string() : " (" + names + ")"));
  }
  if (head == "swap") {
    kind = TargetKind::Swap;
    for (size_t i = 0; i < rig.swaps.size(); ++i) {
      const auto& [name, members] = rig.swaps[i];
      if (rest.rfind(name + ".", 0) != 0) continue;
      const int m = find(members, rest.substr(name.size() + 1));
      if (m < 0) continue;
      index = int(i);
      if (member) *member = m;
      return R::success(true);
    }
    std::string names;
    for (const auto& [name, members] : rig.swaps)
      for (const std::string& m : members) names += (names.empty() ? "" : ", ") + name + "." + m;
    return R::failure("no swap set member '" + rest + "'" + (names.empty() ? std::string(" (the rig has no [[swap]])") : " (" + names + ")"));
  }
  if (head == "trigger") {
    kind = TargetKind::Trigger;
    index = find(rig.triggers, rest);
    if (index >= 0) return R::success(true);
    std::string names;
    for (const std::string& n : rig.triggers) names += (names.empty() ? "" : ", ") + n;
    return R::failure("no trigger '" + rest + "'" + (names.empty() ? std::string(" (the rig has no [[trigger]])") : " (" + names + ")"));
  }
  return R::failure("unknown target '" + t +
                    "' (handle.NAME[.x|.y], rotate.GROUP, pose.NAME, grab, solver.SETTING, morph.A.B, blend.KEY, swap.SET.MEMBER, "
                    "trigger.NAME, physics.NAME.strength|mix, physics.wind|gravity|reset)");
}

Result<bool> parse_chord(const std::string& text, int32_t& key, uint16_t& mod) {
  using R = Result<bool>;
  key = 0;
  mod = 0;
  size_t a = 0;
  while (true) {
    const size_t b = text.find('+', a);
    const std::string part = text.substr(a, b == std::string::npos ? std::string::npos : b - a);
    if (b == std::string::npos) {
      key = SDL_GetKeyFromName(part.c_str());
      if (key == SDLK_UNKNOWN) return R::failure("exit_chord: unknown key '" + part + "' (an SDL key name such as q, F12, Escape)");
      if (mod == 0) return R::failure("exit_chord needs a modifier (ctrl, alt, shift or gui) before the key, such as ctrl+alt+q");
      return R::success(true);
    }
    if (part == "ctrl") mod |= KMOD_CTRL;
    else if (part == "alt") mod |= KMOD_ALT;
    else if (part == "shift") mod |= KMOD_SHIFT;
    else if (part == "gui") mod |= KMOD_GUI;
    else return R::failure("exit_chord: unknown modifier '" + part + "' (ctrl, alt, shift, gui)");
    a = b + 1;
  }
}

WindowKey window_key(const ShowConfig::Kiosk& k, int32_t key, uint16_t mod) {
  if (k.enabled) {
    if (k.key == 0 || key != k.key) return WindowKey::None;
    for (uint16_t m : {uint16_t(KMOD_CTRL), uint16_t(KMOD_ALT), uint16_t(KMOD_SHIFT), uint16_t(KMOD_GUI)})
      if ((k.mod & m) && !(mod & m)) return WindowKey::None;  // (either side's key counts)
    return WindowKey::Quit;
  }
  if (key == SDLK_ESCAPE || key == SDLK_q) return WindowKey::Quit;
  if (key == SDLK_h) return WindowKey::ToggleHud;
  return WindowKey::None;
}

ShowConfig default_show() {
  ShowConfig s;
  s.rate_hz = 60;
  s.iterations = 8;
  s.min_iterations = 2;
  s.late_input = true;
  s.late_input_margin_ms = 0.5;
  s.width = 800;
  s.height = 600;
  s.fullscreen = false;
  s.hud = true;
  s.background = "#f4f1ea";
  return s;
}

Result<ShowConfig> load_show(const std::string& path, const RigLoader& load_rig) {
  try {
    ShowConfig s = default_show();
    s.path = path;
    const toml::table root = parse_file(path);  // the one parse of the file
    read_header(path, root, s);
    read_cast(path, root, s);  // show_cast.cpp
    read_brushed(path, root, s);  // show_pen.cpp
    auto loaded = load_rig(s);
    if (!loaded.ok()) return Result<ShowConfig>::failure(loaded.error);
    const ShowRig& rig = *loaded.value;
    read_devices(path, root, s);
    read_attract(path, root, s);  // show_devices.cpp
    read_scenery(path, root, s);  // show_stage.cpp
    read_props(path, root, s);
    read_groups_and_poses(path, root, s, rig);
    if (const toml::array* bs = array_of_tables(path, root, "binding"))
      for (const toml::node& bn : *bs) s.bindings.push_back(read_binding(path, bn, s, rig));
    read_brushes(path, root, s, rig);  // show_pen.cpp
    read_curves(path, root, s, rig);
    read_behaviors(path, root, s, rig);  // loop/idle.cpp
    return Result<ShowConfig>::success(std::move(s));
  } catch (const ShowError& e) {
    return Result<ShowConfig>::failure(e.message);
  }
}

Result<ShowConfig> read_show_cast(const std::string& path) {
  try {
    ShowConfig s = default_show();
    s.path = path;
    const toml::table root = parse_file(path);
    read_header(path, root, s);
    read_cast(path, root, s);
    return Result<ShowConfig>::success(std::move(s));
  } catch (const ShowError& e) {
    return Result<ShowConfig>::failure(e.message);
  }
}

std::string append_binding(const std::string& path, const std::string& device, const std::string& control,
                           const std::string& target) {
  // (atomically: the show file as it was, comments and all, then the binding)
  return append_atomically(path, "\n[[binding]]  # learned with --learn\ndevice = \"" + device + "\"\ncontrol = \"" + control +
                                     "\"\ntarget = \"" + target + "\"\n");
}

}  // namespace mar
