// Show files (TOML, config/shows/): which character and rig, which devices, how controls
// bind to targets, display and frame rate. See README "Show files" for every key.
#pragma once

#include "devices/device.h"
#include "devices/discover.h"
#include "input/mapping.h"
#include "input/decoder.h"

#include <string>
#include <vector>

namespace mar {

struct ShowDevice {
  std::string name;
  std::string type = "sim";     ///< "sim" (in-process firmware_sim device) or a hardware backend
  std::string sim;              ///< nanokontrol2 | knob_box | pen_tablet | gamepad (hardware: what --simulate presents)
  DeviceSpec hw;                ///< hardware devices: what to look for (type, IDs, lines, port...)
  /// Control names of the device's profile (config/devices/NAME.toml): name -> control text.
  std::vector<std::pair<std::string, std::string>> controls;
  std::string descriptor;       ///< HID report descriptor file (resolved), empty = built-in
  bool descriptor_in_corpus = false;  ///< named with "corpus:" (optional: the corpus may be absent)
  std::string script;           ///< timeline script text
  double bounce_ms = 0, debounce_ms = 0;
  uint32_t seed = 1;
  int line = 0;
};

struct ShowConfig {
  std::string path;             ///< the show file
  std::string character, rig;   ///< resolved paths (character empty: the rig's own)
  double rate_hz = 60;
  int iterations = 8, min_iterations = 2;
  int width = 800, height = 600;
  bool fullscreen = false, hud = true;
  std::string background = "#f4f1ea";
  std::vector<ShowDevice> devices;
  std::vector<Binding> bindings;         ///< resolved against the rig's handles
  std::vector<RotationGroup> groups;
  std::vector<Pose> poses;
  std::vector<std::string> handle_names;
  std::vector<Vec2> handle_rest;
};

/// Parses and checks a show file. Handles, groups and poses are resolved with the rig's
/// handle names and rest positions (`handles`, `rest`); `diag` (the character's bounding
/// box diagonal) sets default ranges. Errors name file:line.
Result<ShowConfig> load_show(const std::string& path, const std::vector<std::string>& handles,
                             const std::vector<Vec2>& rest, double diag);
/// Reads only the [show] table (character and rig paths) so the caller can load the puppet.
Result<ShowConfig> load_show_header(const std::string& path);

/// Parses a control ("cc 7", "cc 7 ch 2", "cc14 1", "nrpn 300", "note 36", "pitchbend",
/// "usage x", "usage 0x0d0030", "button 3", "encoder 2", "pointer") into `out`.
Result<bool> parse_control(const std::string& text, ControlSpec& out);
/// The control grammar's text for a control: parse_control(format_control(c)) gives c back.
std::string format_control(const ControlSpec& c);
/// Parses a target ("handle.NAME.x", "handle.NAME", "rotate.GROUP", "pose.NAME", "grab",
/// "solver.iterations", "solver.rigidity|coupling|position").
Result<bool> parse_target(const std::string& text, const ShowConfig& show, TargetKind& kind, int& index);

/// A binding's control text with the device profile's names replaced ("left-x" -> "usage x");
/// OSC controls ("osc /fader/1") are numbered per device here.
std::string device_control(ShowDevice& d, const std::string& control);
/// The program's data folder (device profiles, example characters, rigs and shows):
/// $MARIONETTE_DATA_DIR, else `share/marionette` beside or above the executable's folder
/// (an installed `bin/marionette`, or a build tree, where CMake links it to config/).
/// Empty when none exists.
std::string data_dir();

/// Finds devices/NAME.toml next to the show's folder (`shows/../devices`), then in data_dir().
std::string find_profile(const std::string& show_path, const std::string& name);

/// VID/PIDs of every profile in data_dir()/devices (for `marionette devices`); a profile that
/// does not parse is left out and named in `errors` ("file:line: what").
std::vector<ProfileId> load_profile_ids(std::vector<std::string>* errors = nullptr);

/// Appends a learned binding to the show file (text appended; the rest is untouched).
std::string append_binding(const std::string& path, const std::string& device, const std::string& control,
                           const std::string& target);

}  // namespace mar
