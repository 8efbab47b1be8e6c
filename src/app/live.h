// The live show: one monotonic clock; per frame drain every device without blocking,
// decode, map, filter, set targets, solve (fixed iterations, warm start), render, present.
// Window and headless modes share this code; headless advances a fixed-rate virtual clock.
#pragma once

#include "app/puppet.h"
#include "app/show.h"
#include "app/stats.h"
#include "devices/device.h"
#include "firmware_sim/sim_device.h"
#include "render/canvas.h"

#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <atomic>

namespace mar {

class HardwareSimulation;

struct RunOptions {
  bool headless = false;
  long frames = -1;          ///< -1: until the scripts end (headless) or the window closes
  double rate = 0;           ///< Hz; 0 = the show's rate
  std::string stats_path, record_path, dump_dir, learn, replay_path;
  bool simulate = false;     ///< present hardware devices' simulators at the kernel interface (umockdev)
  int every = 1;
  bool quiet = false;
  int warmup = 30;           ///< frames before allocations are counted
};

/// SIGINT/SIGTERM end the show cleanly (stats are still written).
void install_quit_handler();
bool quit_requested();

/// Counts heap allocations in the program (set by main; tests install their own).
using AllocationCounter = uint64_t (*)();
void set_allocation_counter(AllocationCounter f);

struct StageTimes {
  Histogram drain, map, solve, render, present, frame, latency;
};

class LiveShow {
 public:
  static Result<std::unique_ptr<LiveShow>> load(const std::string& show_path, const RunOptions& o);
  ~LiveShow();
  /// Runs one frame at show time `t_ns` (virtual in headless, monotonic in a window).
  void frame(int64_t t_ns);
  /// Runs the whole show per the options; returns the exit code.
  int run();
  uint64_t run_hash() const { return hash_; }
  long frames() const { return frames_; }
  const Mapping& mapping() const { return mapping_; }
  const Puppet& puppet() const { return *puppet_; }
  std::string stats_json() const;
  /// Heap allocations counted after warm-up (needs an allocation counter).
  uint64_t allocations_after_warmup() const { return allocs_; }
  bool learned() const { return learned_; }
  /// The show's input sources, index = show device index (nullptr when replaying).
  DeviceSet* devices() { return devices_.get(); }
  /// Ends run() after the current frame (any thread).
  void stop() { stop_ = true; }
  /// Whether frames follow the wall clock (a window, or hardware devices).
  bool realtime() const { return !opt_.headless || has_hardware_; }

 private:
  LiveShow() = default;
  bool open_output(std::string* err);
  void drain(int64_t t_ns);
  void record_wire(const WireRecord& r);
  void record_device(uint16_t source, std::span<const uint8_t> description);
  void regrab(bool down);
  void refactor();
  void draw_hud();
  bool replay_next(int64_t& t_ns, int& iterations);
  std::string open_devices();
  void feedback();

  RunOptions opt_;
  ShowConfig show_;
  std::unique_ptr<Puppet> puppet_;
  Mapping mapping_;
  std::vector<std::unique_ptr<SimDevice>> sims_;   ///< per show device with a sim (in-process or --simulate)
  std::unique_ptr<HardwareSimulation> simulation_; ///< --simulate: hardware sims at the kernel interface
  std::unique_ptr<DeviceSet> devices_;             ///< every show device as a source (not when replaying)
  bool has_hardware_ = false;
  int64_t epoch_ns_ = 0;                           ///< CLOCK_MONOTONIC at show time 0
  std::atomic<bool> stop_{false};
  std::vector<WireRecord> wires_;  ///< this frame's wire records (capacity fixed)
  uint64_t dropped_records_ = 0;
  std::vector<std::unique_ptr<Decoder>> replay_decoders_;  ///< per source, from the recording
  std::vector<Event> events_;   ///< this frame's events (capacity fixed)
  size_t n_events_ = 0;
  uint64_t dropped_events_ = 0;
  std::vector<Vec2> targets_;   ///< handles, then the grab handle's target
  std::unique_ptr<Canvas> canvas_;
  DrawList list_;
  Affine2 view_;
  Rgba background_{244, 241, 234, 255};
  double period_s_ = 1.0 / 60;
  int iterations_ = 8;
  long frames_ = 0;
  uint64_t hash_ = 1469598103934665603ull;
  StageTimes st_;
  long overruns_ = 0, governor_steps_ = 0, iter_sum_ = 0;
  int iter_min_ = 1 << 30, iter_max_ = 0;
  uint64_t allocs_ = 0, alloc_base_ = 0;
  double last_compute_ms_ = 0;
  int64_t last_t_ = 0;
  bool grabbing_ = false;
  long refactorizations_ = 0;
  uint64_t refactor_allocs_ = 0;
  Histogram refactor_us_;
  Histogram quality_;           ///< worst-part distortion per frame, 0.001 % of the height
  int grab_handle_ = -1;        ///< the rig handle a pen grab took over (-1: an extra handle)
  Vec2 grab_offset_ = Vec2::Zero();
  long grabs_ = 0;              ///< pen downs and ups (rank-2 updates, no re-factorisation)
  Histogram grab_us_;
  bool hud_ = true, quit_ = false, learned_ = false;
  std::FILE* record_ = nullptr;
  std::FILE* replay_ = nullptr;
  std::vector<WireRecord> replay_pending_;
};

}  // namespace mar
