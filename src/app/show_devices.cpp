// [[device]] tables for hardware (usb_midi, hid, gpio, tablet, alsa, osc, sdl), the
// device profiles in config/devices/, and [attract] (whose script a device's simulator speaks).
#include "app/show.h"
#include "app/show_toml.h"
#include "firmware_sim/sim_device.h"

#include <cstdio>
#include <span>
#include <sstream>

namespace mar {

using namespace showtoml;

namespace {

constexpr const char* kTypes[] = {"sim", "usb_midi", "hid", "gpio", "tablet", "alsa", "audio", "osc", "sdl"};


// vid/pid/usage: an integer, or pid a list of them.
void ids(const std::string& path, const toml::table& t, DeviceSpec& hw) {
  if (auto* n = t.get("vid")) hw.vid = integer(path, *n, "vid", 0, 0xFFFF);
  if (auto* n = t.get("pid")) {
    if (n->is_array()) {
      hw.pids.clear();
      for (const toml::node& e : *n->as_array()) hw.pids.push_back(integer(path, e, "pid", 0, 0xFFFF));
      hw.pid = -1;
    } else {
      hw.pid = integer(path, *n, "pid", 0, 0xFFFF);
    }
  }
  if (auto* n = t.get("usage_page")) hw.usage_page = integer(path, *n, "usage_page", 0, 0xFFFF);
  if (auto* n = t.get("usage")) hw.usage = integer(path, *n, "usage", 0, 0xFFFF);
  if (auto* n = t.get("product")) hw.product = text(path, *n, "product");
  if (auto* n = t.get("serial")) hw.serial = text(path, *n, "serial");
}

// A message as hex bytes ("96 38 {v}"): `{v}` is the value's byte (its place in *value_at; a
// message without one when value_at is null).
std::vector<uint8_t> hex_message(const std::string& file, const toml::node& n, const char* what, size_t* value_at, size_t* count) {
  const std::string s = text(file, n, what);
  std::istringstream in(s);
  std::vector<uint8_t> out;
  bool has_value = false;
  for (std::string w; in >> w;) {
    if (w == "{v}" && value_at && !has_value) {
      *value_at = out.size();
      out.push_back(0);
      has_value = true;
      continue;
    }
    char* end = nullptr;
    const unsigned long b = std::strtoul(w.c_str(), &end, 16);
    if (w.size() > 2 || *end || b > 0xFF)
      throw ShowError{at(file, n) + ": " + what + ": '" + w + "' is not a byte in hex" + (value_at ? " or {v}" : "")};
    out.push_back(uint8_t(b));
  }
  if (out.empty() || out[0] < 0x80 || out.size() > 64) throw ShowError{at(file, n) + ": " + what + ": a MIDI message of 1..64 bytes"};
  if (value_at && !has_value) throw ShowError{at(file, n) + ": " + what + ": where the value goes: {v}"};
  ++*count;
  return out;
}

// [leds]: NAME = { send = "HEX {v}", on = N, off = N, palette = "...", ring = [LO, HI] }.
void read_leds(const std::string& file, const toml::table& t, ShowDevice& d) {
  for (const auto& [k, v] : t) {
    const toml::table* e = v.as_table();
    const std::string name(k.str());
    if (!e) throw ShowError{at(file, v) + ": led '" + name + "' must be a table { send = \"...\", ... }"};
    check_keys(file, *e, {"send", "on", "off", "palette", "ring"}, "an led");
    DeviceLed led;
    led.name = name;
    for (const auto& [cn, ct] : d.controls)
      if (cn == name) led.control = ct;
    if (led.control.empty()) throw ShowError{at(file, v) + ": led '" + name + "' is no control of [controls]"};
    const toml::node* send = e->get("send");
    if (!send) throw ShowError{at(file, v) + ": led '" + name + "' needs send = \"HEX {v}\""};
    size_t count = 0;
    led.bytes = hex_message(file, *send, "send", &led.value_at, &count);
    if (auto* n = e->get("on")) led.on = int(integer(file, *n, "on", 0, 127));
    if (auto* n = e->get("off")) led.off = int(integer(file, *n, "off", 0, 127));
    if (auto* n = e->get("palette")) {
      led.palette = text(file, *n, "palette");
      std::string names;
      if (led_color(led.palette, "off", &names) < 0) throw ShowError{at(file, *n) + ": no palette '" + led.palette + "' (apc_mini_mk2, launch_control_xl)"};
    }
    if (auto* n = e->get("ring")) {
      const toml::array* a = n->as_array();
      if (!a || a->size() != 2) throw ShowError{at(file, *n) + ": ring = [LO, HI] (the values at either end)"};
      led.ring = true;
      led.lo = int(integer(file, *a->get(0), "ring", 0, 127));
      led.hi = int(integer(file, *a->get(1), "ring", 0, 127));
    }
    d.leds.push_back(std::move(led));
  }
}

void read_profile(const std::string& show_path, const toml::node& where, const std::string& name, ShowDevice& d) {
  const std::string file = find_profile(show_path, name);
  if (file.empty()) throw ShowError{at(show_path, where) + ": no device profile '" + name + "' in config/devices/"};
  read_hardware_profile(file, name, d);
}

}  // namespace

std::string data_dir() {
  if (const char* env = std::getenv("MARIONETTE_DATA_DIR"); env && *env) return env;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  for (const fs::path& d : {exe.parent_path() / ".." / "share" / "marionette", exe.parent_path() / "share" / "marionette"}) {
    if (fs::is_directory(d / "devices", ec)) return fs::weakly_canonical(d, ec).string();
  }
  return {};
}

std::string find_profile(const std::string& show_path, const std::string& name) {
  std::vector<fs::path> dirs{fs::path(show_path).parent_path() / ".." / "devices"};
  if (const std::string d = data_dir(); !d.empty()) dirs.push_back(fs::path(d) / "devices");
  for (const fs::path& dir : dirs)
    if (fs::exists(dir / (name + ".toml"))) return (dir / (name + ".toml")).lexically_normal().string();
  return {};
}

void read_hardware_profile(const std::string& file, const std::string& name, ShowDevice& d) {
  toml::table root;
  Result<std::string> file_text = read_file(file, kMaxTomlBytes, "a device profile");
  if (!file_text.ok()) throw ShowError{file_text.error};
  Result<toml::table> parsed = cfg::parse_toml(*file_text.value, file);
  if (!parsed.ok()) throw ShowError{parsed.error};
  root = std::move(*parsed.value);
  check_keys(file, root, {"device", "controls", "leds"}, "a device profile");
  if (const toml::table* t = root["device"].as_table()) {
    check_keys(file, *t, {"name", "type", "vid", "pid", "usage_page", "usage", "product", "sim", "descriptor", "init", "setup"},
               "[device]");
    if (const toml::node* n = t->get("setup")) {
      if (text(file, *n, "setup") != "korg_external_leds")
        throw ShowError{at(file, *n) + ": setup must be \"korg_external_leds\" (the only one there is)"};
      d.korg_external_leds = true;
    }
    if (const toml::node* n = t->get("init")) {
      const toml::array* a = n->as_array();
      if (!a) throw ShowError{at(file, *n) + ": init must be a list of messages (hex bytes)"};
      for (const toml::node& m : *a) {
        size_t unused = 0;
        d.init.push_back(hex_message(file, m, "init", nullptr, &unused));
      }
    }
    if (auto* n = t->get("type")) d.hw.type = text(file, *n, "type");
    ids(file, *t, d.hw);
    if (auto* n = t->get("sim")) d.sim = text(file, *n, "sim");
    if (auto* n = t->get("descriptor")) {
      const std::string desc = text(file, *n, "descriptor");
      d.descriptor = resolve(file, desc);
      d.descriptor_in_corpus = desc.rfind("corpus:", 0) == 0;
    }
  }
  if (const toml::table* c = root["controls"].as_table())
    for (const auto& [k, v] : *c) d.controls.emplace_back(std::string(k.str()), text(file, v, "a control"));
  if (const toml::table* l = root["leds"].as_table()) read_leds(file, *l, d);
  d.hw.profile = name;
}


void read_voice(const std::string& path, const toml::table& t, ShowDevice& d) {
  using namespace showtoml;
  if (const toml::node* f = t.get("file")) d.descriptor = resolve(path, text(path, *f, "file"));
  if (const toml::node* p = t.get("pcm")) d.hw.pcm = text(path, *p, "pcm");
  if (const toml::node* c = t.get("calibrate")) {
    const toml::table* ct = c->as_table();
    if (!ct) throw ShowError{at(path, *c) + ": calibrate must be a table: { a = [F1, F2], i = [...], u = [...], e = [...], o = [...] }"};
    static const char* kNames[] = {"a", "i", "u", "e", "o"};
    for (const auto& [k, v] : *ct) {
      int idx = -1;
      for (int i = 0; i < 5; ++i)
        if (k.str() == kNames[i]) idx = i;
      if (idx < 0) throw ShowError{at(path, v) + ": calibrate names a vowel: a, i, u, e or o (not '" + std::string(k.str()) + "')"};
      const Vec2 f = point(path, v, "a vowel's formants");
      if (!(f.x() >= 100 && f.x() <= 2000 && f.y() > f.x() && f.y() <= 5000))
        throw ShowError{at(path, v) + ": a vowel's formants are [F1, F2] in Hz, 100 <= F1 < F2 <= 5000"};
      d.voice[size_t(idx)] = {f.x(), f.y()};
    }
  }
  d.hw.voice = d.voice;
  char buf[32];
  auto usage_text = [&](uint32_t u) {
    std::snprintf(buf, sizeof buf, "usage 0x%08x", unsigned(u));
    return std::string(buf);
  };
  d.controls.push_back({"level", usage_text(voice_usage::kLevel)});
  d.controls.push_back({"onset", usage_text(voice_usage::kOnset)});
  for (Viseme v : {Viseme::Closed, Viseme::A, Viseme::I, Viseme::U, Viseme::E, Viseme::O})
    d.controls.push_back({std::string("viseme ") + viseme_name(v), usage_text(voice_usage::viseme(v))});
}

void check_device_keys(const std::string& path, const toml::table& t) {
  check_keys(path, t,
             {"name", "type", "sim", "descriptor", "script", "script_file", "bounce_ms", "debounce_ms", "seed", "profile",
              "vid", "pid", "serial", "product", "usage_page", "usage", "chip", "encoders", "buttons",
              "steps_per_detent", "host", "port", "source", "sdl", "feedback", "detach_kernel_driver", "file", "calibrate", "pcm",
              "priority"},
             "[[device]]");
}

void read_hardware(const std::string& path, const toml::table& t, ShowDevice& d) {
  bool known = false;
  for (const char* k : kTypes) known = known || d.type == k;
  if (!known) {
    std::string list;
    for (const char* k : kTypes) list += std::string(list.empty() ? "" : ", ") + k;
    throw ShowError{at(path, *t.get("type")) + ": unknown device type '" + d.type + "' (" + list + ")"};
  }
  DeviceSpec& hw = d.hw;
  hw.name = d.name;
  hw.type = d.type;
  if (auto* n = t.get("profile")) {
    read_profile(path, *n, text(path, *n, "profile"), d);
    if (!t.get("type")) d.type = hw.type;
  }
  if (d.type == "sim") return;
  ids(path, t, hw);
  if (auto* n = t.get("chip")) hw.chip = text(path, *n, "chip");
  const int steps = t.get("steps_per_detent") ? integer(path, *t.get("steps_per_detent"), "steps_per_detent", 1, 4) : 4;
  if (auto* n = t.get("encoders")) {
    const toml::array* a = n->as_array();
    if (!a) throw ShowError{at(path, *n) + ": encoders = [[\"A line\", \"B line\"], ...]"};
    for (const toml::node& e : *a) {
      const auto ab = strings(path, e, "an encoder's lines");
      if (ab.size() != 2) throw ShowError{at(path, e) + ": an encoder is [\"A line\", \"B line\"]"};
      hw.encoders.push_back({ab[0], ab[1], steps});
    }
  }
  if (auto* n = t.get("buttons")) hw.buttons = strings(path, *n, "buttons");
  if (auto* n = t.get("debounce_ms")) {
    hw.debounce_ms = number(path, *n, "debounce_ms");
    if (hw.debounce_ms < 0 || hw.debounce_ms > 10000) throw ShowError{at(path, *n) + ": debounce_ms must be 0..10000 ms"};
  }
  if (auto* n = t.get("host")) hw.host = text(path, *n, "host");
  if (auto* n = t.get("port")) hw.port = integer(path, *n, "port", 1, 65535);
  if (auto* n = t.get("source")) hw.alsa_source = text(path, *n, "source");
  if (auto* n = t.get("sdl")) hw.sdl = text(path, *n, "sdl");
  if (auto* n = t.get("feedback")) hw.feedback = boolean(path, *n, "feedback");
  if (auto* n = t.get("detach_kernel_driver")) hw.detach_kernel_driver = boolean(path, *n, "detach_kernel_driver");
  if (d.type == "gpio" && (hw.chip.empty() || (hw.encoders.empty() && hw.buttons.empty())))
    throw ShowError{at(path, t) + ": a gpio device needs chip and encoders and/or buttons (line names)"};
  if (d.type == "sdl" && hw.sdl != "mouse" && hw.sdl != "touch" && hw.sdl != "gamepad")
    throw ShowError{at(path, *t.get("sdl")) + ": sdl = mouse, touch or gamepad"};
}

int led_color(const std::string& palette, const std::string& color, std::string* names) {
  // The APC mini mk2's velocity palette (Akai's protocol), the Launch Control XL's red/green
  // mix (16 x green + red + 12, Novation's programmer's reference).
  static const std::pair<const char*, int> apc[] = {{"off", 0},     {"white", 3},   {"red", 5},     {"orange", 9},
                                                    {"yellow", 13}, {"green", 21},  {"cyan", 33},   {"blue", 45},
                                                    {"purple", 49}, {"magenta", 53}, {"pink", 57}};
  static const std::pair<const char*, int> lcxl[] = {{"off", 12}, {"red", 15}, {"amber", 63}, {"yellow", 62}, {"green", 60}};
  std::span<const std::pair<const char*, int>> p;
  if (palette == "apc_mini_mk2") p = apc;
  else if (palette == "launch_control_xl") p = lcxl;
  if (names) names->clear();
  for (const auto& [n, v] : p) {
    if (color == n) return v;
    if (names) *names += (names->empty() ? "" : ", ") + std::string(n);
  }
  return -1;
}

void read_priority(const std::string& path, const toml::table& t, const ShowDevice& d, Binding& b) {
  SourcePriority& p = b.tf.priority;
  b.tf.has_priority = d.has_priority;
  p.priority = d.priority;
  if (auto* n = t.get("priority")) {
    p.priority = int(integer(path, *n, "priority", -1000, 1000));
    b.tf.has_priority = true;
  }
  auto seconds = [&](const char* key, double& v) {
    const toml::node* n = t.get(key);
    if (!n) return;
    v = number(path, *n, key);
    if (!(v >= 0 && v <= 60)) throw ShowError{at(path, *n) + ": " + key + " must be 0..60 seconds"};
  };
  seconds("hold", p.hold);
  seconds("handover", p.handover);
  const bool drives = b.target == TargetKind::HandleX || b.target == TargetKind::HandleY || b.target == TargetKind::Rotate ||
                      b.target == TargetKind::Setting;
  for (const char* key : {"priority", "hold", "handover"})
    if (const toml::node* n = t.get(key); n && !drives)
      throw ShowError{at(path, *n) + ": " + key + " goes with a target a value drives (handle.NAME.x or .y, rotate.GROUP, solver.SETTING)"};
  if (b.tf.has_priority && !drives) b.tf.has_priority = false;  // (a device's default: buttons and grabs take no part)
}

void read_binding_led(const std::string& path, const toml::node& n, const ShowDevice& d, Binding& b) {
  if (const auto* off = n.as_boolean()) {
    if (off->get()) throw ShowError{at(path, n) + ": led = false (no light), or a colour"};
    b.led = -2;
    return;
  }
  const std::string color = text(path, n, "led");
  const DeviceLed* led = nullptr;
  for (const DeviceLed& l : d.leds)
    if (l.control == b.control.text || l.name == b.control.text) led = &l;
  if (!led) throw ShowError{at(path, n) + ": '" + b.control.text + "' of device '" + d.name + "' has no light (its profile's [leds])"};
  std::string names;
  b.led = led_color(led->palette, color, &names);
  if (b.led < 0)
    throw ShowError{at(path, n) + ": " + (led->palette.empty() ? "this light has one colour: use led = false to keep it dark"
                                                               : "no colour '" + color + "' (" + names + ")")};
}

std::string device_control(ShowDevice& d, const std::string& control) {
  for (const auto& [name, text] : d.controls)
    if (control == name) return text;
  // A pad by its profile's name, as a continuous control: "pad_r1c1 velocity" (the note's
  // velocity while held) or "pad_r1c1 pressure" (its polyphonic key pressure).
  if (const size_t sp = control.rfind(' '); sp != std::string::npos) {
    const std::string base = control.substr(0, sp), what = control.substr(sp + 1);
    for (const auto& [name, text] : d.controls) {
      if (name != base || text.rfind("note ", 0) != 0 || (what != "velocity" && what != "pressure")) continue;
      std::istringstream in(text);
      std::string note, number, rest, w;
      in >> note >> number;
      while (in >> w) rest += " " + w;  // (its channel: "ch N")
      return what == "velocity" ? "note " + number + " velocity" + rest : "polypressure " + number + rest;
    }
  }
  if (control.rfind("osc ", 0) == 0) {
    const std::string addr = control.substr(4);
    size_t i = 0;
    while (i < d.hw.osc_addresses.size() && d.hw.osc_addresses[i] != addr) ++i;
    if (i == d.hw.osc_addresses.size()) d.hw.osc_addresses.push_back(addr);
    char t[32];
    std::snprintf(t, sizeof t, "usage 0x%08zx", size_t(0xFF000000u) | i);
    return t;
  }
  return control;
}

}  // namespace mar

namespace mar {

std::vector<ProfileId> load_profile_ids(std::vector<std::string>* errors) {
  std::vector<ProfileId> out;
  const std::string data = data_dir();
  if (data.empty()) return out;
  const fs::path dir = fs::path(data) / "devices";
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (e.path().extension() != ".toml") continue;
    Result<std::string> file_text = read_file(e.path().string(), kMaxTomlBytes, "a device profile");
    if (!file_text.ok()) continue;  // (not a profile to match against: a folder, a FIFO, too large)
    Result<toml::table> parsed = cfg::parse_toml(*file_text.value, e.path().string());
    if (!parsed.ok()) {
      if (errors) errors->push_back(parsed.error);
      continue;
    }
    {
      const toml::table& t = *parsed.value;
      ProfileId p;
      p.name = e.path().stem().string();
      // A VID or PID that is not a 16-bit whole number matches nothing (-1).
      const auto id = [](const toml::node* n) {
        const auto v = n ? cfg::whole(*n) : std::nullopt;
        return v && *v >= 0 && *v <= 0xFFFF ? int(*v) : -1;
      };
      p.vid = id(t["device"]["vid"].node());
      if (const toml::array* a = t["device"]["pid"].as_array()) {
        for (const toml::node& n : *a) p.pids.push_back(id(&n));
      } else {
        p.pids.push_back(id(t["device"]["pid"].node()));
      }
      out.push_back(p);
    }
  }
  return out;
}

}  // namespace mar

namespace mar {

void read_attract(const std::string& path, const toml::table& root, ShowConfig& s) {
  using namespace showtoml;
  const toml::node* an = root.get("attract");
  if (!an) return;
  const toml::table* t = an->as_table();
  if (!t) throw ShowError{at(path, *an) + ": [attract] must be a table"};
  check_keys(path, *t, {"after", "fade", "device", "script", "script_file", "loop", "take"}, "[attract]");
  AttractConfig& a = s.attract;
  a.line = int(an->source().begin.line);
  auto seconds = [&](const char* key, double lo, double hi, const char* range) {
    const toml::node* n = t->get(key);
    const double v = number(path, *n, key);
    if (!(v >= lo && v <= hi)) throw ShowError{at(path, *n) + ": " + key + " must be " + range + " s"};
    return v;
  };
  if (!t->get("after")) throw ShowError{at(path, *an) + ": [attract] needs after = SECONDS without input"};
  a.after = seconds("after", 1, 86400, "1..86400");
  if (t->get("fade")) a.fade = seconds("fade", 0, 10, "0..10");
  if (t->get("loop")) a.loop = seconds("loop", 0.01, 1e5, "0.01..100000");
  const int sources = (t->get("script") ? 1 : 0) + (t->get("script_file") ? 1 : 0) + (t->get("take") ? 1 : 0);
  if (sources != 1)
    throw ShowError{at(path, *an) + ": [attract] plays one of script, script_file (with device) or take"};
  if (const toml::node* n = t->get("take")) {
    a.take = resolve(path, text(path, *n, "take"));
    if (t->get("device") || t->get("loop"))
      throw ShowError{at(path, *n) + ": a take replays this show's own devices (no device or loop)"};
    return;
  }
  const toml::node* dn = t->get("device");
  if (!dn) throw ShowError{at(path, *an) + ": an attract script needs device = \"NAME\" (whose simulator speaks it)"};
  a.device = device_named(path, *dn, s);
  const std::string& dname = s.devices[size_t(a.device)].name;
  const ShowDevice& d = s.devices[size_t(a.device)];
  if (d.sim.empty()) throw ShowError{at(path, *dn) + ": device '" + dname + "' has no sim = ... to speak the script"};
  // The script is checked here, with the line it is on ("file:line: what").
  std::string where = path;
  int first_line = 0;
  if (const toml::node* n = t->get("script")) {
    a.script = text(path, *n, "script");
    first_line = int(n->source().begin.line);
  } else {
    a.script = read_script_file(path, *t->get("script_file"), &where);
  }
  auto sim = make_sim_device(d.sim, "", 0, 1);
  if (!sim.ok()) throw ShowError{at(path, *dn) + ": " + sim.error};
  if (auto ok = (*sim.value)->load_script(a.script); !ok.ok()) {
    int line = 0;
    if (std::sscanf(ok.error.c_str(), "line %d:", &line) == 1) {
      const size_t colon = ok.error.find(':');
      throw ShowError{where + ":" + std::to_string(first_line + line) + ":" + ok.error.substr(colon + 1)};
    }
    throw ShowError{where + ":" + std::to_string(first_line) + ": attract script: " + ok.error};
  }
}

}  // namespace mar
