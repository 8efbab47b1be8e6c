// Show files (TOML, config/shows/): which character and rig, which devices, how controls
// bind to targets, display and frame rate. See docs/show-files.md for every key.
#pragma once

#include "devices/device.h"
#include "devices/discover.h"
#include "input/mapping.h"
#include "motion/behavior.h"
#include "input/decoder.h"

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace mar {

/// A controller's light, from its profile's [leds] (app/loop/leds.h): the MIDI message that sets
/// it, with the value's place in it, and the values that light it and put it out.
struct DeviceLed {
  std::string name;              ///< the profile's control name
  std::string control;           ///< its control text ("note 56")
  std::vector<uint8_t> bytes;    ///< the message, the value's byte at value_at
  size_t value_at = 0;
  int on = 127, off = 0;
  std::string palette;           ///< colours by name: "apc_mini_mk2", "launch_control_xl" (empty: none)
  bool ring = false;             ///< an encoder's ring: the bound value from lo (the low end) to hi
  int lo = 0, hi = 127;
};

/// A controller's colours by name (palette "apc_mini_mk2" or "launch_control_xl"): the value, or
/// -1 with `names` the ones there are.
int led_color(const std::string& palette, const std::string& color, std::string* names = nullptr);

struct ShowDevice {
  std::string name;
  std::string type = "sim";     ///< "sim" (in-process firmware_sim device) or a hardware backend
  std::string sim;              ///< nanokontrol2 | knob_box | pen_tablet | gamepad | microphone (hardware: what --simulate presents)
  DeviceSpec hw;                ///< hardware devices: what to look for (type, IDs, lines, port...)
  /// Control names of the device's profile (config/devices/NAME.toml): name -> control text.
  std::vector<std::pair<std::string, std::string>> controls;
  std::string descriptor;       ///< HID report descriptor file (resolved), empty = built-in; a microphone's WAV `file`
  /// A voice's calibration (`calibrate = { a = [F1, F2], ... }`): F1, F2 for a, i, u, e, o (0: default).
  std::array<std::array<double, 2>, 5> voice{};
  bool descriptor_in_corpus = false;  ///< named with "corpus:" (optional: the corpus may be absent)
  std::string script;           ///< timeline script text
  std::vector<DeviceLed> leds;  ///< its profile's lights
  std::vector<std::vector<uint8_t>> init;  ///< its profile's messages on connecting (a mode for its LEDs)
  /// Its profile's `setup = "korg_external_leds"`: on connecting, its scene's LED mode is set to
  /// External (input/korg_scene.h) before any light is sent.
  bool korg_external_leds = false;
  double bounce_ms = 0, debounce_ms = 0;
  uint32_t seed = 1;
  int line = 0;
  /// `priority`: its bindings' default (input/arbitration.h); unset: bindings state their own.
  int priority = 0;
  bool has_priority = false;
};

/// [[scenery]]: a drawing or picture (SVG or PNG) on the stage that does not move: a backdrop
/// behind the character, or something in front of it.
struct ShowScenery {
  std::string file;  ///< resolved
  enum Fit { Cover, Contain, Placed } fit = Cover;  ///< fills the canvas (cropped), fits in it, or `at` + `width`
  Vec2 at{0, 0};     ///< Placed: its top-left corner, canvas pixels
  double width = 0;  ///< Placed: its width, canvas pixels (its height follows)
  bool front = false;
  int line = 0;
};

/// [[prop]]: a drawing (SVG or PNG) a part of the character holds: it follows that part's
/// motion (the part's best rigid fit to its rest shape, each frame).
struct ShowProp {
  std::string file;      ///< resolved
  std::string part;      ///< the holding part: a shape id of the character
  bool has_at = false;
  Vec2 at{0, 0};         ///< where the prop's centre goes at rest, character units (default: the part's centre)
  double width = 0;      ///< its width, character units (0: its own)
  double rotation = 0;   ///< degrees at rest (clockwise on screen)
  bool front = true;     ///< drawn over the character (false: behind it)
  int line = 0;
};

/// [[brush]]: a pen that sculpts the character's outline (the brush of seed 004,
/// app/loop/brush.h). It becomes a pointer binding on the target `brush` (`NAME.brush` in a cast).
struct ShowBrush {
  int device = 0;
  int who = 0;                    ///< the cast's character (0: a show's single rig)
  double radius_lo = 20, radius_hi = 60;  ///< canvas px, light to full pressure
  double strength = 1;            ///< 0..1: how firmly the brushed outline takes the drag
  /// On lifting the pen: spring back, hold, or spring back while the character blends into a
  /// key pose (`key`: a recall of it over the same seconds, as `pose.KEY` asks).
  enum Release : uint8_t { Spring, Hold, Key } release = Spring;
  double release_seconds = 0.5;   ///< spring, key: back over this
  int key = -1;                   ///< key: the rig key it blends into (-1: rest)
  int line = 0;
};

/// [[curve]]: a pen whose stroke a chain of the character's parts takes (the drawn curve of
/// seed 001, app/loop/curve.h). A pointer binding on the target `curve` (`NAME.curve`).
struct ShowCurve {
  int device = 0;
  int who = 0;
  /// `chain`: a chain of parts lays along the stroke (loop/curve.h); `contour`: the outline
  /// segment the stroke runs along takes its shape (loop/contour.h).
  enum Fit : uint8_t { Chain, Contour } fit = Chain;
  std::vector<std::string> parts;  ///< the chain, the part nearest `from` first (contour: the parts whose outlines it fits; none: all)
  std::string from;                ///< the part (or handle) it hangs from (a chain's)
  double strength = 1;
  ShowBrush::Release release = ShowBrush::Hold;
  double release_seconds = 1.0;  ///< (a bent chain springing back faster whips its secondary motion)
  int key = -1;                  ///< release = key: the rig key (-1: rest)
  int line = 0;
};

/// [attract]: what an unattended show plays when nobody touches it (app/loop/attract.h).
struct AttractConfig {
  double after = 0;              ///< seconds without input before it plays (0: no attract)
  double fade = 0.6;             ///< crossfade seconds, both ways
  int device = -1;               ///< script: the show device whose simulator speaks it
  std::string script;            ///< a timeline script in that simulator's language
  double loop = 0;               ///< script: repeat period (0: its length plus one second)
  std::string take;              ///< or a recording (`run --record`) of this show, looped
  int line = 0;                  ///< show-file line of [attract]
};

/// A parsed, validated show file. Every default lives in default_show().
/// [physics]: what every chain of the rig feels (motion/chain.h), and the fixed step's rate.
struct ShowPhysics {
  double rate = 120;          ///< steps per second, 30..240
  Vec2 gravity{0, 980};       ///< character units / s², down
  Vec2 wind{0, 0};
  /// sync = "beat": the wind and the chains' gusts blow in a pulse on every beat of the music
  /// (motion/beat_clock.h), strongest on the beat, still between.
  bool sync_beat = false;
};

/// [[behavior]]: an idle behaviour (motion/behavior.h) and the target it drives.
struct ShowBehavior {
  std::string name;
  BehaviorSpec spec;
  std::string target_text;
  TargetKind target = TargetKind::Trigger;
  int index = 0, member = 0;
  int line = 0;
};

/// [[character]]: one of the show's cast, with its own rig and its place on the canvas.
struct ShowCharacter {
  std::string name;             ///< what the show's names start with: `NAME.handle.left-hand`
  std::string character, rig;   ///< resolved paths (character empty: the rig's own)
  bool has_position = false;
  Vec2 position{0, 0};          ///< where the centre of its rest box goes, canvas px (default: the cast side by side)
  double scale = 1;             ///< 1: the size it would have alone on the canvas (its share of it, side by side)
  double rotation = 0;          ///< degrees, clockwise on screen, about its position
  int z = 0;                    ///< drawing order: higher in front (equal: the order of the tables)
  bool shown = true;            ///< on stage at the start (its NAME.on-stage trigger's first state)
  /// How it enters and leaves when its NAME.on-stage trigger changes: "fade", "slide-left",
  /// "slide-right", "slide-up", "slide-down" (from and to beyond that edge) or "cut".
  std::string entrance = "fade";
  double entrance_seconds = 0.6;
  int line = 0;
};

struct ShowConfig {
  std::string path;             ///< the show file
  std::string character, rig;   ///< resolved paths (character empty: the rig's own); a cast: the first's
  /// [[character]] tables: the cast. Empty: [show]'s rig alone, a cast of one whose names have no
  /// character in front.
  std::vector<ShowCharacter> cast;
  // (no defaults here: default_show() has them all)
  double rate_hz = 0;
  int iterations = 0, min_iterations = 0;
  /// On the wall clock a frame wakes its predicted compute plus a margin before it is due, and
  /// reads its inputs then (app/loop/late_input.h); false: it reads when it is due.
  bool late_input = false;
  double late_input_margin_ms = 0;
  /// [show] images = "anywhere": an SVG character may name images outside its own folder
  /// (default "beside": such an image is skipped with a warning).
  bool images_anywhere = false;
  /// [show] threads: the threads a cast's actors solve on, the frame's own included (0: from 4
  /// characters on, one a character up to the machine's cores; fewer, the frame's alone).
  int threads = 0;
  int width = 0, height = 0;
  bool fullscreen = false, hud = false;
  /// [display] vsync: a window's present waits for the display's refresh (no tearing; the show's
  /// rate should be the display's), and --stats estimates input to photon.
  bool vsync = false;
  /// [display] screen: the screen a window or fullscreen show opens on (-1: SDL's choice), or
  /// a substring of its name (screen_name, matched when the window opens).
  int screen = -1;
  std::string screen_name;
  /// [output] width, height: the canvas every output draws (dumps, streams, files); 0: the
  /// window's size ([display] width, height). A window shows it scaled to fit, letterboxed.
  int out_width = 0, out_height = 0;
  /// [output] pipewire: the canvas published as a PipeWire video source named after the show
  /// (output/pipewire_out.h).
  bool out_pipewire = false;
  /// [osc_out]: the show's state sent as OSC (output/osc_out.h); port 0: off.
  struct OscOut {
    std::string host = "127.0.0.1", prefix = "/marionette";
    int port = 0;
    double rate = 30;
  } osc_out;
  /// [kiosk] (or `run --kiosk`): fullscreen on `display`, cursor hidden, no HUD, no quit keys
  /// (Escape, q and closing the window do nothing); only `exit_chord` (e.g. "ctrl+alt+shift+q",
  /// empty: none) or a signal ends the show.
  struct Kiosk {
    bool enabled = false;
    int display = 0;
    std::string exit_chord;
    int32_t key = 0;   ///< SDL keycode of the chord's key
    uint16_t mod = 0;  ///< SDL KMOD_CTRL / KMOD_ALT / KMOD_SHIFT / KMOD_GUI bits it needs
  } kiosk;
  AttractConfig attract;
  std::string background;
  std::vector<ShowDevice> devices;
  std::vector<ShowScenery> scenery;      ///< [[scenery]]: drawings that stay still, behind or in front
  std::vector<ShowProp> props;           ///< [[prop]]: drawings a part of the character holds
  std::vector<ShowBrush> brushes;        ///< [[brush]]: pens that sculpt an outline
  std::vector<ShowCurve> curves;         ///< [[curve]]: pens whose stroke a chain takes
  /// The characters a [[brush]] names ("" for a single rig), known before the rigs load: their
  /// feature frames are made finer (kSculptSpacing).
  std::vector<std::string> brushed;
  std::vector<Binding> bindings;         ///< resolved against the rig's handles
  std::vector<RotationGroup> groups;
  std::vector<Pose> poses;
  ShowPhysics physics;
  std::vector<ShowBehavior> behaviors;
};

/// The defaults of every show key (rate 60 Hz, 8 iterations, floor 2, 800x600, HUD on...).
ShowConfig default_show();

/// What a show's names are resolved against, known once its rig is loaded: the rig's handles
/// (names, rest positions), the character's diagonal (default ranges) and the settings a
/// binding may drive as `solver.NAME` (the loop's `iterations`, the solver's parameters).
struct ShowRig {
  std::vector<std::string> handles;
  std::vector<Vec2> rest;
  double diag = 1;
  struct SettingName {
    std::string name;
    std::optional<std::pair<double, double>> default_range;  ///< a binding's range when it gives none
  };
  std::vector<SettingName> settings;  ///< index = Mapping setting index
  /// The rig's swap sets (name, members) and triggers, for swap.SET.MEMBER and trigger.NAME.
  std::vector<std::pair<std::string, std::vector<std::string>>> swaps;
  std::vector<std::string> triggers;
  /// Key poses a pose.NAME may recall along the interpolation (empty when the rig's method
  /// cannot interpolate them).
  std::vector<std::string> keys;
  /// A cast ([[character]]): each character's own names (its rig as a show of its own would
  /// see it) and where they start in the lists above, which hold them all, prefixed `NAME.`
  /// (settings after `iterations`, the show's own). Empty: a show's single rig.
  struct Member {
    std::string name;
    size_t handle0 = 0, setting0 = 0, swap0 = 0, trigger0 = 0, key0 = 0;
  };
  std::vector<Member> cast;
  std::vector<ShowRig> cast_rigs;
  /// A handle's character's diagonal (a binding's default range).
  double diag_of(int handle) const;
  /// A handle's character in the cast (-1: a show's single rig).
  int member_of(int handle) const;
};
/// The cast's names as one ShowRig: every character's, prefixed with its name.
ShowRig cast_rig(const std::vector<std::string>& names, std::vector<ShowRig> rigs);
/// Loads the rig a show names (called with the [show] table read: character and rig paths,
/// iterations); an error is returned as is.
using RigLoader = std::function<Result<ShowRig>(const ShowConfig& header)>;

/// A show's [show] table and its cast ([[character]] tables) alone, without loading a rig (what
/// `rig --show SHOW --character NAME` opens). Errors name file:line.
Result<ShowConfig> read_show_cast(const std::string& path);

/// Parses the show file once and validates it: the [show] table first, then `rig(header)`,
/// then devices, groups, poses and bindings resolved against what it returns. Errors name
/// file:line.
Result<ShowConfig> load_show(const std::string& path, const RigLoader& rig);

/// Parses a key chord ("ctrl+alt+q": modifiers ctrl, alt, shift, gui, then one SDL key name).
Result<bool> parse_chord(const std::string& text, int32_t& key, uint16_t& mod);

/// What a key does in a show's window: quit (Escape or q; in a kiosk only its exit chord),
/// toggle the HUD (h; never in a kiosk), or nothing.
enum class WindowKey { None, Quit, ToggleHud };
WindowKey window_key(const ShowConfig::Kiosk& kiosk, int32_t key, uint16_t mod);

/// Parses a control ("cc 7", "cc 7 ch 2", "cc14 1", "nrpn 300", "note 36", "pitchbend",
/// "usage x", "usage 0x0d0030", "button 3", "encoder 2", "pointer") into `out`.
Result<bool> parse_control(const std::string& text, ControlSpec& out);
/// The control grammar's text for a control: parse_control(format_control(c)) gives c back.
std::string format_control(const ControlSpec& c);
/// Parses a target ("handle.NAME.x", "handle.NAME", "rotate.GROUP", "pose.NAME" (a show
/// [[pose]], else a rig key or rest), "grab", "solver.SETTING" for a setting `rig` offers,
/// "morph.A.B", "blend.KEY", "swap.SET.MEMBER", "trigger.NAME") against the show and the rig.
/// In a cast every target of a rig starts with its character's name ("robot.handle.left-hand",
/// "robot.grab": index is the character, as `member` is for "robot.pose.KEY"); rotate.GROUP,
/// pose.NAME (a [[pose]]) and solver.iterations are the show's.
Result<bool> parse_target(const std::string& text, const ShowConfig& show, const ShowRig& rig, TargetKind& kind,
                          int& index, int* member = nullptr);

/// A binding's control text with the device profile's names replaced ("left-x" -> "usage x");
/// OSC controls ("osc /fader/1") are numbered per device here.
std::string device_control(ShowDevice& d, const std::string& control);
/// Reads device profile `file` (config/devices/NAME.toml) into `d`: identity, simulator, control
/// names, lights and init messages. Throws ShowError with file:line.
void read_hardware_profile(const std::string& file, const std::string& name, ShowDevice& d);
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
