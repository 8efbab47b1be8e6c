// Command implementations behind the CLI (main.cpp holds only argument parsing).
// Exit codes: 0 success, 1 runtime failure, 2 bad input or usage.
#pragma once

#include "character/character.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace mar {

enum ExitCode { kExitOk = 0, kExitRuntime = 1, kExitBadInput = 2 };

struct RenderArgs {
  std::string input;
  std::string output;
  std::string size;        ///< "WxH" or empty
  std::string background;  ///< "RRGGBB", "transparent" or empty
  std::string mask;
  int supersample = 1;
};
int cmd_render(const RenderArgs& a);

struct InspectArgs {
  std::string input;
  std::string mask;
  bool json = false;
  std::string rig;      ///< with a rig: the seed 000 Table 1 columns and the handles
  std::string overlay;  ///< with a rig: PNG of the frame drawn over the character
};
int cmd_inspect(const InspectArgs& a);
int cmd_inspect_rig(const InspectArgs& a);  // pose_commands.cpp

struct PoseArgs {
  std::string input;
  std::string rig;
  std::vector<std::string> targets;  ///< "NAME=X,Y"
  int iterations = -1;               ///< -1 = the rig's
  std::string dump;
  std::string output;
  std::string size;
  std::string background;
  bool overlay = false;
  std::string mask;                  ///< PNG character: mask image (non-black = figure)
  std::vector<std::string> settings; ///< "NAME=VALUE": a solver parameter (half_width, stiffness.arm, ...)
  std::string save_key;              ///< append the pose's targets to the rig as [[key]] NAME
};
int cmd_pose(const PoseArgs& a);

struct InterpArgs {
  std::string input;
  std::string rig;
  std::string mask;
  std::string from = "rest", to;    ///< key names ("rest": the rest pose)
  double t = -1;                    ///< one in-between at t (0..1)
  int steps = 0;                    ///< or steps + 1 frames from t = 0 to 1
  bool linear = false;              ///< the naive linear blend of frame vertices instead
  std::string dump;                 ///< JSON: per step, t, frame vertices and sub-shapes
  std::string output;               ///< PNG of the one in-between (--t)
  std::string out_dir;              ///< PNG per step (--steps)
  std::string size, background;
};
int cmd_interp(const InterpArgs& a);

struct Puppet;
/// Renders the puppet's current shapes (and optionally its solver's structure) into a PNG.
int write_picture(Puppet& p, const std::string& path, int w, int h, const Rgba& bg, bool overlay,
                  std::span<const Vec2> handle_points);
/// The document size of a character, clamped to 1..8192.
std::pair<int, int> doc_size(const Character& ch);

struct ViewArgs {
  std::vector<std::string> inputs;
  std::string out_dir = "marionette-out";
  std::string size;  ///< per-character tile size, "WxH"
  double seconds = 0;  ///< window mode: close after this long (0 = until closed)
  bool headless = false;
  bool software = false;
  int supersample = 2;     ///< headless PNGs only
  std::string screenshot;  ///< window mode: save the first frame's pixels here
};
int cmd_view(const ViewArgs& a);

struct RunArgs {
  std::string show;
  bool headless = false;
  long frames = -1;
  double rate = 0;
  std::string stats, record, dump_frames, learn, replay;
  std::string dump_poses;  ///< every frame's shapes as JSON lines
  int every = 1;
  bool simulate = false;
  bool kiosk = false;
  bool realtime = false;
  std::string screenshot;
  int supersample = 1;
  bool aliased = false;
  std::string video, codec = "ffv1";  ///< a video take (output/video_out.h)
  std::string size;                   ///< WxH: the canvas (replay --size)
  bool force = false;                 ///< replay a take of another show
};
/// `run` and `replay` (replay: `replay` set to the recording).
int cmd_run(const RunArgs& a);

struct CalibrateArgs {
  std::string wav;  ///< a, i, u, e, o said in order, a pause between
};
/// `calibrate`: a voice's vowel templates from a recording, as a `calibrate = { ... }` line.
int cmd_calibrate(const CalibrateArgs& a);

struct RigArgs {
  std::string input;   ///< the character
  std::string mask;
  std::string output;  ///< the rig to write ("-": print it; "": open the rig studio)
  std::string show;    ///< a starter show to write beside it (needs `output`); with `character_name`, the show to open
  std::string character_name;  ///< studio: the cast's character of `show` to open (its rig and drawing)
  std::string device = "nanokontrol2";  ///< the starter show's device
  std::string preview;  ///< a picture of what was found (rig_preview.h)
  bool bones = false;   ///< a limb inside one shape turns whole at its joint (AutoRigOptions::bones)
  // The rig studio (no `output`):
  std::string rig;         ///< the rig to edit and save (default: <character stem>.toml here)
  std::string size;        ///< the canvas, "WxH" (default 960x720)
  double seconds = 0;      ///< close after this long (0: when the performer quits)
  bool software = false;   ///< SDL's software renderer
  std::string screenshot;  ///< save the first frame's window here
};
/// `rig`: the automatic rig of a character (rig/auto_rig.h).
int cmd_rig(const RigArgs& a);

struct DevicesArgs {
  bool json = false;
};
/// `devices`: what every backend finds here, its status and any problem.
int cmd_devices(const DevicesArgs& a);

/// The inspect report of a character, as JSON or as the text table (shared by inspect
/// with and without a rig).
nlohmann::ordered_json inspect_json(const Character& ch);
void print_inspect_text(const Character& ch);

/// Parses "WxH" (both 1..8192).
std::optional<std::pair<int, int>> parse_size(const std::string& s);
/// Whether a window can open (DISPLAY or WAYLAND_DISPLAY is set).
bool display_available();
/// Parses "RRGGBB", "#RRGGBB" or "transparent".
std::optional<Rgba> parse_background(const std::string& s);

/// Applies the --size and --background flags of a picture command (each only when given)
/// to `w`, `h` and `bg`; prints the error and returns false when one is malformed.
/// The character's load warnings (and a solver's, for a puppet) on stderr, one per line.
void print_warnings(const Character& ch);
bool apply_picture_flags(const std::string& size, const std::string& background, int& w, int& h, Rgba& bg);

}  // namespace mar
