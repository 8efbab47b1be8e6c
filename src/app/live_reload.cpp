// Reloading a running show (SIGHUP, or a saved edit: loop/file_watch.h). The edited files are
// loaded into a new LiveShow, which then takes over what the running one holds when the edit
// left it alone: the clock (the pacer, the frame count, the statistics), the devices with their
// connections, the simulators with their scripts' positions, the window and the outputs. An
// edit to the devices or to the canvas's size starts those over, and says so.
#include "app/live.h"
#include "app/simulate.h"
#include "firmware_sim/sim_device.h"

#include <SDL.h>

#include <atomic>
#include <filesystem>
#include <iostream>
#include <thread>
#include <tuple>

namespace mar {
namespace {

bool same_device(const ShowDevice& a, const ShowDevice& b) {
  auto key = [](const ShowDevice& d) {
    const DeviceSpec& h = d.hw;
    return std::tie(d.name, d.type, d.sim, d.controls, d.descriptor, d.voice, d.script, d.bounce_ms, d.debounce_ms, d.seed,
                    h.type, h.vid, h.pid, h.pids, h.serial, h.product, h.usage_page, h.usage, h.chip, h.buttons,
                    h.debounce_ms, h.host, h.port, h.osc_addresses, h.alsa_source, h.sdl, h.feedback, h.pcm);
  };
  if (key(a) != key(b) || a.hw.encoders.size() != b.hw.encoders.size()) return false;
  for (size_t i = 0; i < a.hw.encoders.size(); ++i) {
    const auto &x = a.hw.encoders[i], &y = b.hw.encoders[i];
    if (std::tie(x.a, x.b, x.steps_per_detent) != std::tie(y.a, y.b, y.steps_per_detent)) return false;
  }
  return true;
}

}  // namespace

// An edit being prepared: the thread that prepares it owns a share, so a job given up (past
// kReloadSeconds, or at the show's end) finishes on its own without touching the show.
struct ReloadJob {
  std::atomic<bool> done{false};
  Result<std::unique_ptr<LiveShow>> result;
  std::string cause;
  int64_t started_ns = 0;
  long started_frame = 0;
};

void LiveShow::start_reload(const std::string& cause) {
  if (reload_job_) {  // one at a time: the newer edit is prepared when this one is done
    reload_again_ = true;
    reload_job_->cause = cause;
    return;
  }
  auto job = std::make_shared<ReloadJob>();
  job->cause = cause;
  job->started_ns = monotonic_ns();
  job->started_frame = stats_.frames;
  RunOptions o = opt_;
  o.quiet = true;  // (its warnings were said when the show was loaded; a bad edit is said here)
  std::thread([job, path = show_.path, o, keep = keepable()]() mutable {
    job->result = prepare(path, o, std::move(keep));
    job->done.store(true, std::memory_order_release);
  }).detach();
  reload_job_ = std::move(job);
  reload_again_ = false;
}

bool LiveShow::reload_ready() {
  if (!reload_job_) return false;
  if (!reload_job_->done.load(std::memory_order_acquire)) {
    if (double(monotonic_ns() - reload_job_->started_ns) * 1e-9 > kReloadSeconds) {
      const std::string why = show_.path + ": preparing the edit took over " + std::to_string(int(kReloadSeconds)) + " s";
      std::cerr << "error: " << why << " (reload refused; the running show goes on)" << std::endl;
      tell_reload(reload_job_->cause, why);  // (counted apart by the frame loop, as reload_ready() is)
      reload_job_.reset();  // (its thread ends on its own)
    }
    return false;
  }
  if (reload_again_) {  // saved again while it was prepared: prepare the newest
    const std::string cause = reload_job_->cause;
    reload_job_.reset();
    start_reload(cause);
    return false;
  }
  reload_cause_ = reload_job_->cause;
  prepare_frames_ = stats_.frames - reload_job_->started_frame;
  return true;
}

Result<std::unique_ptr<LiveShow>> LiveShow::take_prepared() {
  if (!reload_job_ || !reload_job_->done.load(std::memory_order_acquire))
    return Result<std::unique_ptr<LiveShow>>::failure("no reload prepared");
  auto r = std::move(reload_job_->result);
  reload_job_.reset();
  reload_asked_ = false;
  return r;
}

std::string LiveShow::keeps(const LiveShow& old) const {
  const ShowConfig &a = show_, &b = old.show_;
  if (old.playback_) return "a replay";
  if (a.devices.size() != b.devices.size()) return "the devices";
  for (size_t i = 0; i < a.devices.size(); ++i)
    if (!same_device(a.devices[i], b.devices[i])) return "device '" + a.devices[i].name + "'";
  if (std::tie(a.width, a.height, a.out_width, a.out_height, a.fullscreen, a.screen, a.screen_name, a.kiosk.enabled,
               a.kiosk.display) != std::tie(b.width, b.height, b.out_width, b.out_height, b.fullscreen, b.screen,
                                            b.screen_name, b.kiosk.enabled, b.kiosk.display))
    return "[display] or [output]";
  if ((background_.a < 1) != (old.background_.a < 1)) return "the background's transparency";
  auto shapes = [](const LiveShow& s) {
    size_t n = 0;
    for (const auto& actor : s.actors_) n += actor->puppet().shapes.size();
    return n;
  };
  if (!opt_.dump_poses.empty() && shapes(*this) != shapes(old)) return "the pose dump's shapes";
  if (a.rate_hz != b.rate_hz) return "the rate";
  return {};
}

void LiveShow::release() {
  // Starting over: the outputs finish their files and the devices and the window are let go,
  // before the new show opens its own.
  released_ = true;
  if (started_) outputs_->finish(opt_.quiet);
  if (recorder_) recorder_->flush();
  if (simulation_) simulation_->stop();
  devices_.reset();
  simulation_.reset();
  sims_.clear();
  hud_panel_.reset();
  canvas_.reset();
}

void LiveShow::adopt(LiveShow& old) {
  // The run goes on, as one object (LiveRun): the options (open_output may have turned a window
  // without a display headless), the devices as connected and the simulators where their
  // scripts are, the clock and the music time, the stats and counts, the file watch, the window,
  // the outputs and the recording.
  const bool drawn = old.stats_frames_drawn();
  static_cast<LiveRun&>(*this) = std::move(static_cast<LiveRun&>(old));
  ++reloads_;
  if (watch_) watch_->watch(watched_files());  // (an edit may name new files)
  // where the controls and the handles were
  mapping_.carry_from(old.mapping_);
  // Each character that was in the old cast (by name) goes on from where it was: its chains
  // swing on, and where it was drawn, when it is the same drawing, the next frames blend from it.
  // The stages that read the last frame's pose (the chains hang from it) read the old one, not
  // the rest pose: a chain's anchor does not leap at the reload.
  for (auto& a : actors_)
    for (const auto& o : old.actors_)
      if (o->name() == a->name()) {
        a->carry_from(*o);
        if (drawn) a->carry_shapes_from(*o);
      }
  grabbed_ = -1;  // (the new solvers hold nothing)
  // the HUD's lines follow the new show's devices and bindings
  if (canvas_->is_window()) {
    hud_panel_ = std::make_unique<Hud>(show_);
    if (const std::string e = hud_panel_->load_font(canvas_->window_renderer()); !e.empty() && !opt_.quiet)
      std::cerr << "warning: the HUD has no text: " << e << "\n";
  }
  const int ss = std::clamp(opt_.supersample, 1, 8);
  place_cast(canvas_->width(), canvas_->height(), ss);
  reserve_layers();
  stage_.place(canvas_->width(), canvas_->height(), ss);
  use_backdrop();
  if (started_) {  // the OSC address space follows the rig
    OutputsSpec out;
    osc_names(out);
    if (const std::string e = outputs_->relayout(out, outputs_drawing()); !e.empty() && !opt_.quiet)
      std::cerr << "warning: " << e << " (OSC out stays off)\n";
  }
}

void LiveShow::reloaded(const std::string& what, const std::string& refused) {
  struct Apart {  // (what the swap allocated, to the end of this)
    LiveShow& s;
    ~Apart() { s.alloc_base_ += allocation_count() - s.swap_allocs_; }
  } apart{*this};
  tell_reload(what, refused);
}

void LiveShow::tell_reload(const std::string& what, const std::string& refused) {
  const std::string stem = std::filesystem::path(show_.path).stem().string();
  if (!refused.empty()) {
    ++refused_;
    if (hud_panel_) hud_panel_->set_notice("edit refused: " + refused, true);
    return;
  }
  last_reload_ = what;
  const std::string note = "reloaded " + what;
  if (hud_panel_) hud_panel_->set_notice(note, false);
  if (canvas_ && canvas_->is_window())
    SDL_SetWindowTitle(canvas_->sdl_window(), ("marionette - " + stem + " (" + note + ")").c_str());
}

}  // namespace mar
