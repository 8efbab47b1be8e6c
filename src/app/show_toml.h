// Show-file reading helpers (show.cpp, show_devices.cpp): the shared config TOML helpers and
// path resolution for show files. Errors are thrown as ShowError (a cfg::ConfigError) with
// file:line and caught at the loader's edge.
#pragma once

#include "app/show.h"
#include "base/config_toml.h"
#include "base/read_file.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <cstdlib>
#include <string>

namespace mar::showtoml {

namespace fs = std::filesystem;

// The shared helpers (base/config_toml.h) under the names the show readers use.
using ShowError = cfg::ConfigError;
using cfg::at;
using cfg::boolean;
using cfg::check_keys;
using cfg::integer;
using cfg::number;
using cfg::point;
using cfg::strings;
using cfg::text;

inline std::string resolve(const std::string& show_path, const std::string& p) {
  if (p.empty() || fs::path(p).is_absolute()) return p;
  // "corpus:" paths name files in the shared test corpus (MARIONETTE_CORPUS_DIR or the
  // build's default), so shows can use real devices' descriptors without copying them.
  if (p.rfind("corpus:", 0) == 0) {
    const char* env = std::getenv("MARIONETTE_CORPUS_DIR");
    return (fs::path(env && *env ? env : MARIONETTE_DEFAULT_CORPUS_DIR) / p.substr(7)).string();
  }
  return (fs::path(show_path).parent_path() / p).lexically_normal().string();
}

/// The text of a `script_file` (resolved against the show file); refused with the key's line.
inline std::string read_script_file(const std::string& show_path, const toml::node& n, std::string* resolved = nullptr) {
  const std::string f = resolve(show_path, text(show_path, n, "script_file"));
  Result<std::string> t = read_file(f, kMaxScriptBytes, "a script");
  if (!t.ok()) throw ShowError{at(show_path, n) + ": script file " + t.error};
  if (resolved) *resolved = f;
  return std::move(*t.value);
}

/// The index of the [[device]] the key `dev` names; refused with its line when there is none.
inline int device_named(const std::string& path, const toml::node& dev, const ShowConfig& s) {
  const std::string name = text(path, dev, "device");
  for (size_t i = 0; i < s.devices.size(); ++i)
    if (s.devices[i].name == name) return int(i);
  throw ShowError{at(path, dev) + ": no [[device]] named '" + name + "'"};
}

/// An array of tables ([[key]]), or nullptr when absent; anything else is refused.
inline const toml::array* array_of_tables(const std::string& path, const toml::table& root, const char* key) {
  const toml::node* n = root.get(key);
  if (!n) return nullptr;
  const toml::array* a = n->as_array();
  if (!a || !a->is_array_of_tables())
    throw ShowError{at(path, *n) + ": use [[" + std::string(key) + "]] tables"};
  return a;
}

/// A pair [a, b] of numbers.
inline std::pair<double, double> pair_of(const std::string& path, const toml::node& n, const char* what) {
  const toml::array* a = n.as_array();
  if (!a || a->size() != 2) throw ShowError{at(path, n) + ": " + what + " must be [a, b]"};
  return {number(path, *a->get(0), what), number(path, *a->get(1), what)};
}

}  // namespace mar::showtoml

namespace mar {
struct ShowDevice;
/// [[device]] keys (sim and hardware).
void check_device_keys(const std::string& path, const toml::table& t);
/// A voice's keys (a microphone: `file`, `calibrate`) and its control names (level, onset,
/// viseme closed|a|i|u|e|o).
void read_voice(const std::string& path, const toml::table& t, ShowDevice& d);
/// Reads a hardware device's keys (and its profile) into `d.hw` / `d.controls`.
void read_hardware(const std::string& path, const toml::table& t, ShowDevice& d);
struct Binding;
/// A binding's `led`: a colour of its device's palette, or false for none.
void read_binding_led(const std::string& path, const toml::node& n, const ShowDevice& d, Binding& b);
/// A binding's `priority`, `hold` and `handover` (its device's priority when it states none).
void read_priority(const std::string& path, const toml::table& t, const ShowDevice& d, Binding& b);
struct ShowConfig;
/// [attract] (after the devices: a script names the device whose simulator speaks it).
void read_attract(const std::string& path, const toml::table& root, ShowConfig& s);
/// [physics] (app/loop/physics.cpp).
void read_physics(const std::string& path, const toml::table& root, ShowConfig& s);
struct ShowRig;
/// [[scenery]] and [[prop]] (show_stage.cpp): drawings on the stage, still or held.
/// [[character]] tables (show_cast.cpp): the cast; and a target of a cast's show.
void read_cast(const std::string& path, const toml::table& root, ShowConfig& s);
Result<bool> parse_cast_target(const std::string& t, const ShowConfig& s, const ShowRig& rig, TargetKind& kind, int& index,
                               int* member);
void read_scenery(const std::string& path, const toml::table& root, ShowConfig& s);
void read_props(const std::string& path, const toml::table& root, ShowConfig& s);
/// [[brush]] (show_pen.cpp): each a pointer binding on its character's brush.
void read_brushed(const std::string& path, const toml::table& root, ShowConfig& s);
void read_brushes(const std::string& path, const toml::table& root, ShowConfig& s, const ShowRig& rig);
/// [[curve]] (show_pen.cpp): each a pointer binding on its character's curve.
void read_curves(const std::string& path, const toml::table& root, ShowConfig& s, const ShowRig& rig);
/// [[group]] and [[pose]] (show_stage.cpp), named by the rig's handles.
void read_groups_and_poses(const std::string& path, const toml::table& root, ShowConfig& s, const ShowRig& rig);
/// [[behavior]] (app/loop/idle.cpp), after the bindings: targets resolve the same way.
void read_behaviors(const std::string& path, const toml::table& root, ShowConfig& s, const ShowRig& rig);
}  // namespace mar
