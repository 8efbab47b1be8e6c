// The live show. Each frame runs the design's stages in order —
//   inputs -> map -> poses -> motion -> solve -> render -> present
// — each a short method below, built from small units with their own tests (app/loop/:
// recording, run stats and run_hash, budget governor, pen grab, HUD, learn, pacing). One
// monotonic clock; window and headless modes share this code (headless advances a
// fixed-rate virtual clock).
#pragma once

#include "app/loop/actor.h"
#include "app/loop/attract.h"
#include "app/loop/governor.h"
#include "app/loop/hud.h"
#include "app/loop/grab.h"
#include "app/loop/file_watch.h"
#include "app/loop/late_input.h"
#include "app/loop/leds.h"
#include "app/loop/light_route.h"
#include "app/loop/music.h"
#include "app/loop/pacing.h"
#include "app/loop/idle.h"
#include "app/loop/key_poses.h"
#include "app/loop/outputs.h"
#include "app/loop/physics.h"
#include "app/loop/stage_drawings.h"
#include "app/loop/recording.h"
#include "app/loop/service.h"
#include "app/loop/run_stats.h"
#include "app/puppet.h"
#include "interp/interpolation.h"
#include "app/show.h"
#include "base/worker_pool.h"
#include "devices/device.h"
#include "firmware_sim/sim_device.h"
#include "render/canvas.h"

#include <atomic>
#include <array>
#include <memory>
#include <string>

namespace mar {

class HardwareSimulation;
struct ReloadJob;

struct RunOptions {
  bool headless = false;
  long frames = -1;          ///< -1: until the scripts end (headless) or the window closes
  double rate = 0;           ///< Hz; 0 = the show's rate
  std::string stats_path, record_path, dump_dir, learn, replay_path;
  std::string dump_poses;    ///< every frame's shapes as JSON lines (output/pose_dump.h)
  bool simulate = false;     ///< present hardware devices' simulators at the kernel interface (umockdev)
  int every = 1;
  bool quiet = false;
  bool kiosk = false;        ///< as the show's [kiosk] (run --kiosk)
  bool realtime = false;     ///< headless on the wall clock (run --realtime): not reproducible
  int late_input = -1;       ///< on the wall clock, late input (-1: the show's [show] late_input; 0 off; 1 on)
  std::string screenshot;    ///< a window's pixels at the last of `frames` frames, as PNG
  int supersample = 1;       ///< the canvas at N x, box-filtered for dumps (a reference path)
  bool aliased = false;      ///< SDL's aliased triangles (run --aliased, to compare)
  std::string video, codec = "ffv1";  ///< a video take of the canvas (output/video_out.h)
  int width = 0, height = 0; ///< the canvas, over the show's [output] (replay --size)
  int warmup = 30;           ///< frames before allocations are counted
  bool force = false;        ///< replay a take of another show (replay --force)
};

/// SIGINT/SIGTERM end the show cleanly (stats are still written); SIGHUP asks for the show file
/// to be read again (take_reload_request; `marionette run` validates it first).
void install_quit_handler();
bool quit_requested();
bool take_reload_request();

/// Counts heap allocations in the program (set by main; tests install their own).
using AllocationCounter = uint64_t (*)();
void set_allocation_counter(AllocationCounter f);

/// What a show's names resolve against once its rig is loaded (load_show's RigLoader): the
/// puppet's handles, the loop's and the solver's settings, key poses, swap sets and triggers.
ShowRig show_rig(const Puppet& p, const ShowConfig& header);
/// The canvas a show draws on: [output]'s size, else the window's (a run's --size before either).
std::array<int, 2> canvas_size(const RunOptions& o, const ShowConfig& sh);

/// A running show's puppet a reload may keep: a character (by name; "" for a single rig) whose
/// files are unchanged (Puppet::stamp), loaded the same way, is not loaded again.
struct KeptPuppet {
  std::string name, character, rig;
  std::array<int, 2> canvas{0, 0};
  bool images_anywhere = false;
  std::shared_ptr<Puppet> puppet;
};

/// What a reload that keeps the running show's devices carries into the edited show, as one
/// object (LiveShow::adopt moves it whole): the run's options, the devices and their
/// simulators, the clock, the run's stats and counts, the file watch, the window and its draw
/// list, the outputs and the recording. The rest of a show is its own: the edited show's cast
/// and mapping, which take over where the old ones were by name (Mapping::carry_from,
/// Actor::carry_from).
struct LiveRun {
  RunOptions opt_;
  // inputs
  std::vector<std::unique_ptr<SimDevice>> sims_;   ///< per show device with a sim (in-process or --simulate)
  std::unique_ptr<HardwareSimulation> simulation_; ///< --simulate: hardware sims at the kernel interface
  std::unique_ptr<DeviceSet> devices_;             ///< every show device as a source (not when replaying)
  bool has_hardware_ = false;
  std::vector<DeviceState> device_states_;         ///< for the HUD (sized at load)
  std::vector<Event> last_events_;                 ///< for the HUD: each device's last control
  uint64_t dropped_events_ = 0, dropped_records_ = 0;
  long sim_waits_ = 0, sim_timeouts_ = 0;          ///< --simulate on the wall clock: frames that waited for the players / gave up
  double sim_max_wait_ms_ = 0;
  // the clock
  Pacer pacer_{1.0 / 60, false};
  LateInput late_;                                 ///< on the wall clock: when a frame wakes; the latency split
  MusicTime beat_;                                 ///< MIDI clock's music time (sync = "beat")
  int64_t last_t_ = 0;
  double last_compute_ms_ = 0;
  // the run's stats and counts
  RunStats stats_;
  uint64_t allocs_ = 0, alloc_base_ = 0;
  uint64_t swap_allocs_ = 0;                       ///< the allocation count when a prepared reload ended run()
  uint64_t present_allocs_ = 0;                    ///< a window's present (the window system's), after warm-up
  bool started_ = false;
  int reloads_ = 0, refused_ = 0;
  long prepare_frames_ = 0;                        ///< frames played while the last edit was prepared
  std::unique_ptr<FileWatch> watch_;               ///< the show's files, on the wall clock
  ServiceNotifier* service_ = nullptr;             ///< under systemd: READY, then WATCHDOG while frames come
  // the window and the outputs
  std::unique_ptr<Canvas> canvas_;
  DrawList list_;                                  ///< (its buffers' capacity: a new drawing's frames allocate nothing)
  bool hud_ = true;
  std::unique_ptr<Recorder> recorder_;
  std::unique_ptr<FrameOutputs> outputs_ = std::make_unique<FrameOutputs>();  ///< dumps, video, PipeWire, OSC out
};

class LiveShow : private LiveRun {
 public:
  /// Loads a show. `previous`: a reload of that running show (app/live_reload.cpp): the new
  /// show takes over its clock, devices, simulators, window and outputs where the edit left
  /// them alone, and starts them over (previous lets go of its own first) where it did not.
  static Result<std::unique_ptr<LiveShow>> load(const std::string& show_path, const RunOptions& o,
                                                LiveShow* previous = nullptr);
  /// Reads and checks a show file as load() would — the show, its rig, its character, every
  /// binding — without opening a device or a window. Empty when it would load.
  static std::string validate(const std::string& show_path);
  /// load() in two steps, for a reload that never stalls a running show: prepare() reads and
  /// prepares everything a show needs (the show file, the rig, the character, the solver, the
  /// key poses, the simulators' scripts) and may run on any thread; take_over() opens the
  /// window, the devices and the outputs, or takes them over from `previous` (on its thread).
  /// `keep`: the running show's puppets (keepable()), each used instead of loading its
  /// character again when its files are unchanged (kept() names those).
  static Result<std::unique_ptr<LiveShow>> prepare(const std::string& show_path, const RunOptions& o,
                                                   std::vector<KeptPuppet> keep = {});
  std::vector<KeptPuppet> keepable() const;
  /// The characters a reload kept as they were loaded (their files unchanged): not prepared again.
  const std::vector<std::string>& kept() const { return kept_; }
  static Result<std::unique_ptr<LiveShow>> take_over(std::unique_ptr<LiveShow> s, LiveShow* previous);
  /// run() returned because SIGHUP or a saved edit asked for the show file again, and the
  /// edited show has been prepared (take_prepared()).
  bool reload_asked() const { return reload_asked_; }
  /// The show prepared for the reload (prepare()'s result: the error, file:line, of a bad edit).
  Result<std::unique_ptr<LiveShow>> take_prepared();
  /// How long preparing an edit may take before the reload is given up (the show goes on).
  static constexpr double kReloadSeconds = 30;
  /// What asked: "SIGHUP", or the saved files' names ("show.toml, figure.toml").
  const std::string& reload_cause() const { return reload_cause_; }
  /// After a reload: says what happened in the HUD and the window's title; `refused`: the
  /// edit's error (file:line), and the running show goes on. What the swap allocated (from
  /// the end of run() on: the old show let go, the new one's notices) is the reload's, counted
  /// apart from the frames'.
  void reloaded(const std::string& what, const std::string& refused = {});
  /// Reloads so far; what the last one started over (empty: nothing, all was kept).
  int reloads() const { return reloads_; }
  const std::string& restarted() const { return restarted_; }
  /// Frames the show played while the last edit was prepared (on a thread of its own).
  long frames_while_preparing() const { return prepare_frames_; }
  /// A reload that could not keep this show let go of its devices, window and outputs.
  bool released() const { return released_; }
  /// Under a service manager: presented frames are counted for its watchdog (the caller owns it
  /// across reloads).
  void set_service(ServiceNotifier* s) { service_ = s; }
  ~LiveShow();
  /// Runs one frame at show time `t_ns` (virtual in headless, monotonic in a window).
  void frame(int64_t t_ns);
  /// Runs the whole show per the options; returns the exit code.
  int run();
  uint64_t run_hash() const { return stats_.hash.value(); }
  long frames() const { return stats_.frames; }
  const Mapping& mapping() const { return mapping_; }
  /// Whether the cast's character `who` is drawn at `p` (its units) as last posed: inside a
  /// shown closed part, or within 3 % of its diagonal of an outline (where a brush touches).
  /// What one pen with tools on several characters takes as its tip goes down.
  bool pen_over(int who, const Vec2& p) const;
  /// The attract loop ([attract]), or nullptr.
  const Attract* attract() const { return attract_.get(); }
  /// The cast's first character's puppet (a show's single rig).
  const Puppet& puppet() const { return actors_.front()->puppet(); }
  /// The threads the cast's actors solve on (1: the frame's alone).
  int solve_threads() const { return pool_ ? pool_->threads() : 1; }
  /// The cast, in the order of its [[character]] tables.
  const std::vector<std::unique_ptr<Actor>>& actors() const { return actors_; }
  std::string stats_json() const;
  /// Heap allocations counted after warm-up (needs an allocation counter).
  uint64_t allocations_after_warmup() const { return allocs_; }
  bool learned() const { return learned_; }
  /// The show's input sources, index = show device index (nullptr when replaying).
  DeviceSet* devices() { return devices_.get(); }
  /// The show's identity in its takes (loop/recording.h).
  uint64_t identity() const { return show_identity(show_); }
  /// This frame's handle targets of the whole cast, in the mapping's order (after the crossfade,
  /// the key poses and the motion): what the solvers got.
  std::span<const Vec2> targets() const { return targets_; }
  /// When the last simulated device's script ends, from the show's start (0: none has one).
  int64_t scripts_end_ns() const;
  /// Ends run() after the current frame (any thread).
  void stop() { stop_ = true; }
  /// Whether frames follow the wall clock: a window, real hardware devices, or --realtime.
  /// Otherwise (headless: in-process simulators, --simulate's bench, a replay) the show runs on
  /// a virtual clock, and what it computes is a function of the show, its files and the
  /// devices' scripts alone: wall-clock time is measured and reported, never used.
  bool realtime() const { return !opt_.headless || opt_.realtime || (has_hardware_ && !opt_.simulate); }

 private:
  LiveShow() = default;
  bool open_output(std::string* err);
  std::string keeps(const LiveShow& old) const;  ///< empty: this show can take over `old`'s clock and devices
  void adopt(LiveShow& old);
  void release();
  void start_reload(const std::string& cause);   ///< prepares the edited show on a thread of its own
  bool reload_ready();                           ///< between frames: the prepared show is there
  void tell_reload(const std::string& what, const std::string& refused);  ///< reloaded()'s notices
  std::string begin();                           ///< once, at the first run(): outputs, pacing, the watch
  std::string open_devices();

  // The stages of a frame.
  void inputs(int64_t t_ns);
  void map(int64_t t_ns);
  void poses();     ///< key poses: the handles follow the interpolated base pose (morph/blend settings, recalls)
  void motion();    ///< secondary motion: the rig's chains at a fixed step (loop/physics.h)
  void solve();
  void render();
  void present();
  void finish(int64_t t_ns, double compute_us);

  void apply_settings();
  void feedback();
  /// Between frames at show time `t_ns`: a binding still waiting for soft takeover a second
  /// after its first wait is said, once. Returns whether any is still to be decided.
  bool tell_takeover_waits(int64_t t_ns);
  bool takeover_pending_ = false;
  void await_simulation(int64_t t);  ///< --simulate: until the simulated devices are written through `t`
  void replay_device(uint16_t source, std::span<const uint8_t> description);
  bool handle_window_events();
  bool learn_from_events();

  ShowConfig show_;
  std::vector<std::unique_ptr<Actor>> actors_;     ///< the cast (loop/actor.h): one for a show's single rig
  std::vector<Actor*> z_order_;                    ///< the cast back to front
  std::unique_ptr<WorkerPool> pool_;               ///< a cast's actors solve on it (started at load)
  std::vector<double> quality_;                    ///< each actor's pose quality this frame
  void place_cast(int w, int h, int ss);   ///< each actor's view on a w x h canvas
  std::vector<std::string> watched_files() const;  ///< the show's, every rig's and drawing's
  void reserve_layers();                           ///< the canvas's room for the cast's layers
  void osc_names(OutputsSpec& out) const;          ///< OSC out's names: the rig's, or the cast's
  void cast_state();                               ///< a cast's handles and keys for the outputs
  Bounds cast_box_;                                ///< a cast's rest boxes together on the canvas (the HUD keeps off it)
  std::vector<uint8_t> cast_cover_;                ///< where their drawings cover it (kCoverCells^2)
  std::vector<Vec2> cast_handles_;                 ///< (sized at load)
  std::vector<double> cast_keys_;
  std::vector<Points> cast_shapes_;                ///< (a pose dump's)
  std::vector<char> cast_shown_;
  Character cast_drawing_;                         ///< a cast's shapes' ids, for the outputs
  const Character& outputs_drawing();              ///< the lead's drawing, or the cast's
  std::span<Vec2> slice(const Actor& a) { return std::span<Vec2>(targets_).subspan(a.ranges().handle0, a.ranges().handles); }
  Actor& lead() { return *actors_.front(); }
  const Actor& lead() const { return *actors_.front(); }
  Mapping mapping_;
  // inputs
  LightRoute lights_{show_, sims_, devices_};      ///< the controllers' lights: to a simulator or through the device set
  std::vector<WireRecord> wires_;                  ///< this frame's wire records (capacity fixed)
  std::vector<Event> events_;                      ///< this frame's events (capacity fixed)
  size_t n_events_ = 0;
  std::unique_ptr<Playback> playback_;
  std::vector<WireRecord> replay_wires_;
  std::vector<std::unique_ptr<Decoder>> replay_decoders_;  ///< per source, from the recording
  std::vector<WireStats> replay_retired_;                  ///< counts of a source's earlier connections
  // map
  std::unique_ptr<Attract> attract_;               ///< [attract]: plays when nobody touches the show
  bool shown_by_attract_ = false;                  ///< swaps and triggers follow the attract's mapping
  int setting_iterations_ = 0;                     ///< Mapping setting: the solver's iteration count
  double dt_ = 0;                                  ///< this frame's step, seconds
  // swap sets and triggers (what shows): the whole cast's, each actor's a range
  std::vector<int> swap_counts_, swap_members_;
  std::vector<char> triggers_on_;
  int stage_trigger0_ = 0;                         ///< a cast's NAME.on-stage triggers, after the rigs' 
  IdleStage idle_;                                 ///< [[behavior]]: blinks, breathing, looking about
  LedFeedback leds_;                               ///< controllers' lights from the show's state
  Governor governor_{8, 2};
  int grabbed_ = -1;                               ///< the actor the pen holds (-1: none)
  std::vector<Vec2> targets_;                      ///< the cast's handles' targets, mapping order
  long refactorizations_ = 0;
  uint64_t refactor_allocs_ = 0;
  Histogram refactor_us_;
  // render, present
  StageDrawings stage_;        ///< [[scenery]] and [[prop]] (loop/stage_drawings.h)
  void use_backdrop();         ///< the canvas takes the scenery behind, drawn once at load
  bool stats_frames_drawn() const { return stats_.frames > 0; }
  Rgba background_{244, 241, 234, 255};
  std::unique_ptr<Hud> hud_panel_;                 ///< a window's HUD (glyphs made at load)
  // the run
  double marks_[3] = {0, 0, 0};                    ///< this frame's read, ready and presented (now_us)
  int64_t newest_ns_ = -1;                         ///< this frame's newest input (show clock; -1: none)
  static uint64_t allocation_count();
  double quality_pct_ = 0;       ///< this frame's pose quality (the HUD)
  int worst_actor_ = -1, worst_shape_ = -1;  ///< where the show's worst distortion so far was (--stats)
  long worst_frame_ = 0;
  std::atomic<bool> stop_{false};
  bool quit_ = false, learned_ = false, reload_asked_ = false, released_ = false;
  std::string reload_cause_, restarted_, last_reload_;
  std::vector<std::string> kept_;
  std::shared_ptr<ReloadJob> reload_job_;        ///< an edit being prepared (live_reload.cpp)
  bool reload_again_ = false;                      ///< a newer edit came while it was
};

}  // namespace mar
