// `marionette run` and `marionette replay`, and the stats JSON.
#include "app/commands.h"
#include "app/live.h"
#include "base/read_file.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <iostream>

namespace mar {

std::string LiveShow::stats_json() const {
  using nlohmann::json;
  auto stage = [](const Histogram& h) {
    return json{{"p50", h.quantile(0.5)}, {"p99", h.quantile(0.99)}, {"max", h.max()}};
  };
  json stages = json::object();
  for (size_t k = 0; k < size_t(Stage::Count); ++k) stages[stage_name(Stage(k))] = stage(stats_.stage[k]);
  stages["frame"] = stage(stats_.frame);
  json devices = json::array();
  for (size_t i = 0; i < show_.devices.size(); ++i) {
    json d = {{"name", show_.devices[i].name}, {"type", show_.devices[i].type}, {"sim", show_.devices[i].sim}};
    if (devices_) {
      const DeviceSet& set = *devices_;
      const DeviceSet::Status st = set.status(i);
      d["status"] = show_.devices[i].type == "sim" ? "present" : device_state_name(st.state);
      d["records"] = st.records;
      d["events"] = st.events;
      d["malformed"] = st.malformed;
      if (show_.devices[i].type != "sim") {
        d["identity"] = set.backend(i).identity();
        d["node"] = set.backend(i).node();
        d["problem"] = set.problem(i);
        d["unplugs"] = st.unplugs;
        d["reconnects"] = st.reconnects;
        d["max_outage_ms"] = st.max_outage_ms;
      }
    } else {  // a replay: the recording's decoders
      const Decoder* dec = i < replay_decoders_.size() ? replay_decoders_[i].get() : nullptr;
      WireStats w = i < replay_retired_.size() ? replay_retired_[i] : WireStats{};
      if (dec) {
        w.records += dec->stats().records;
        w.events += dec->stats().events;
        w.malformed += dec->stats().malformed;
      }
      d["status"] = dec ? "replayed" : "not in the recording";
      d["records"] = w.records;
      d["events"] = w.events;
      d["malformed"] = w.malformed;
    }
    devices.push_back(d);
  }
  json j = {
      {"show", show_.path},
      {"frames", stats_.frames},
      {"rate_hz", 1.0 / pacer_.period_s()},
      // Where the canvas is drawn ("gpu": by the window's accelerated renderer, with fringes;
      // "software": the rasterizer), and the window's renderer ("software", "opengl", ...;
      // "none" headless).
      {"canvas", {{"width", canvas_->width()}, {"height", canvas_->height()},
                  {"antialias", canvas_->antialias()},
                  {"drawn_by", canvas_->gpu() ? "gpu" : "software"},
                  {"window_renderer", canvas_->is_window() ? canvas_->renderer_name() : "none"}}},
      {"stages_us", stages},
      {"overruns", stats_.overruns},
      // What the wall clock could change: on the virtual clock nothing (overruns are measured
      // only); on the wall clock (a window, hardware, --realtime) the governor's reductions and
      // --simulate frames that had to wait for late players, or gave up on them.
      {"clock", {{"mode", playback_ ? "replay" : realtime() ? "realtime" : "virtual"},
                 {"governor_reductions", governor_.reductions()},
                 {"simulation_waits", sim_waits_},
                 {"simulation_max_wait_ms", sim_max_wait_ms_},
                 {"simulation_timeouts", sim_timeouts_}}},
      {"iterations", {{"configured", show_.iterations}, {"floor", show_.min_iterations},
                      {"min", stats_.frames ? stats_.iter_min : 0}, {"max", stats_.iter_max}, {"mean", stats_.iter_mean()},
                      {"governor_reductions", governor_.reductions()}}},
      {"latency_us", {{"p50", stats_.latency.quantile(0.5)}, {"p99", stats_.latency.quantile(0.99)},
                      {"max", stats_.latency.max()}, {"events", stats_.latency.count()}}},
      {"events", {{"mapped", mapping_.stats().matched}, {"total", mapping_.stats().events},
                  {"dropped", dropped_events_}, {"records_dropped", dropped_records_},
                  {"takeover_waits", mapping_.stats().takeover_waits}}},
      {"refactorizations", {{"count", refactorizations_}, {"p50_us", refactor_us_.quantile(0.5)}, {"max_us", refactor_us_.max()},
                             {"heap_allocations", refactor_allocs_}}},
      {"quality", {{"unit", "% of character height"},
                   {"worst_part_distortion", {{"p50", stats_.quality.quantile(0.5) / 1000},
                                              {"p99", stats_.quality.quantile(0.99) / 1000},
                                              {"max", stats_.quality.max() / 1000}}},
                   // (where the max was: the part and its character, and the frame)
                   {"worst_part", [&] {
                      if (worst_actor_ < 0 || size_t(worst_actor_) >= actors_.size() || worst_shape_ < 0) return json(nullptr);
                      const Actor& a = *actors_[size_t(worst_actor_)];
                      const auto& shapes = a.puppet().character.shapes;
                      if (size_t(worst_shape_) >= shapes.size()) return json(nullptr);
                      return json{{"character", a.name()}, {"part", shapes[size_t(worst_shape_)].id}, {"frame", worst_frame_}};
                    }()}}},
      {"behaviors", [&] {
         json a = json::array();
         for (size_t i = 0; i < idle_.size(); ++i)
           a.push_back({{"name", show_.behaviors[i].name}, {"target", show_.behaviors[i].target_text}, {"blinks", idle_.behavior(i).blinks()}});
         return a;
       }()},
      {"music", {{"bpm", beat_.clock().bpm()}, {"locked", beat_.clock().locked()}, {"beats", beat_.clock().beats()}}},
      {"physics", [&] {  // (the cast's chains together)
         size_t chains = 0;
         long steps = 0, resets = 0, reverts = 0;
         for (const auto& a : actors_) {
           chains += a->physics().size();
           steps += long(a->physics().steps());
           resets += long(a->physics().resets());
           reverts += long(a->physics().reverts());
         }
         return json{{"chains", chains}, {"steps", steps}, {"resets", resets}, {"reverted_steps", reverts}};
       }()},
      {"grabs", [&] {  // (the cast's together; p50 of the character grabbed most)
         long count = 0;
         double max_us = 0;
         const Grab* most = &lead().grab();
         for (const auto& a : actors_) {
           count += a->grab().count();
           max_us = std::max(max_us, a->grab().cost_us().max());
           if (a->grab().count() > most->count()) most = &a->grab();
         }
         return json{{"count", count}, {"p50_us", most->cost_us().quantile(0.5)}, {"max_us", max_us}};
       }()},
      {"cast", [&] {
         json c = json::array();
         for (const auto& a : actors_) c.push_back(a->name().empty() ? a->puppet().rig.path : a->name());
         return c;
       }()},
      {"heap_allocations_after_warmup", allocs_},
      // Reloads (SIGHUP, a saved edit): how many, how many edits were refused, what the last one
      // was, and what it started over (empty: the clock, devices and outputs went on).
      {"reloads", {{"count", reloads_}, {"refused", refused_}, {"last", last_reload_}, {"restarted", restarted_},
                   {"frames_while_preparing", prepare_frames_}}},
      {"window_present_allocations_after_warmup", present_allocs_},
      {"warmup_frames", opt_.warmup},
      {"attract", attract_ ? json{{"starts", attract_->starts()}, {"handovers", attract_->handovers()},
                                  {"seconds_shown", attract_->seconds_shown()}}
                           : json(nullptr)},
      {"devices", devices},
      {"run_hash", [&] {
         char buf[20];
         std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(run_hash()));
         return std::string(buf);
       }()},
  };
  outputs_->add_stats(j);  // pose_dump, frame_dump, video, pipewire, osc_out
  if (late_.timed()) late_.add_stats(j);
  if (!leds_.empty()) {  // the lights sent, and what each simulator shows
    leds_.add_stats(j);
    json shown = json::object();
    for (size_t d = 0; d < sims_.size() && d < show_.devices.size(); ++d)
      if (sims_[d] && !sims_[d]->leds().empty()) shown[show_.devices[d].name] = sims_[d]->leds();
    j["leds"]["simulators_show"] = shown;
  }  // the frame against its deadline; the latency split
  return j.dump(2) + "\n";
}

int cmd_run(const RunArgs& a) {
  if (a.every < 1) {
    std::cerr << "error: --every must be >= 1\n";
    return kExitBadInput;
  }
  if (a.supersample < 1 || a.supersample > 8) {
    std::cerr << "error: --supersample must be 1..8\n";
    return kExitBadInput;
  }
  if (a.rate != 0 && !(a.rate >= 1 && a.rate <= 1000)) {  // (0: the show's own rate)
    std::cerr << "error: --rate must be 1..1000 Hz\n";
    return kExitBadInput;
  }
  RunOptions o;
  o.headless = a.headless;
  o.frames = a.frames;
  o.rate = a.rate;
  o.stats_path = a.stats;
  o.record_path = a.record;
  o.dump_dir = a.dump_frames;
  o.dump_poses = a.dump_poses;
  o.every = a.every;
  o.learn = a.learn;
  o.replay_path = a.replay;
  o.simulate = a.simulate;
  o.kiosk = a.kiosk;
  o.realtime = a.realtime;
  o.screenshot = a.screenshot;
  o.supersample = a.supersample;
  o.aliased = a.aliased;
  o.video = a.video;
  o.codec = a.codec;
  o.force = a.force;
  // Where the outputs go is checked before the show starts: a bad path is said at once, not
  // after the whole run.
  for (const auto& [path, what] : {std::pair{a.stats, "--stats"}, {a.record, "--record"}, {a.dump_poses, "--dump-poses"}, {a.video, "--video"}}) {
    if (const std::string e = output_problem(path); !e.empty()) {
      std::cerr << "error: " << what << " " << e << "\n";
      return kExitRuntime;
    }
  }
  if (!a.dump_frames.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(a.dump_frames, ec);
    if (ec || !std::filesystem::is_directory(a.dump_frames)) {
      std::cerr << "error: --dump-frames " << a.dump_frames << ": cannot make the folder (" << (ec ? ec.message() : "not a folder") << ")\n";
      return kExitRuntime;
    }
  }
  if (const std::string e = check_video_take(a.video, a.codec); !e.empty()) {
    std::cerr << "error: " << e << "\n";
    return kExitBadInput;
  }
  if (!a.size.empty()) {
    const auto sz = parse_size(a.size);
    if (!sz || sz->first < 16 || sz->second < 16) {
      std::cerr << "error: --size must be WxH with 16..8192 pixels each, got '" << a.size << "'\n";
      return kExitBadInput;
    }
    o.width = sz->first;
    o.height = sz->second;
  }
  auto show = LiveShow::load(a.show, o);
  if (!show.ok()) {
    std::cerr << "error: " << show.error << "\n";
    return kExitBadInput;
  }
  std::unique_ptr<LiveShow> live = std::move(*show.value);
  ServiceNotifier service;  // systemd's notify protocol, when it runs the show
  if (service.active()) live->set_service(&service);
  while (true) {
    const int rc = live->run();
    if (!live->reload_asked()) return rc;
    // SIGHUP (systemctl reload) or a saved edit: the edited files are checked first; a bad edit
    // keeps the running show and says what is wrong with file:line, in the log and the HUD.
    // The edit was read and prepared on a thread of its own while the show played
    // (live_reload.cpp); here it takes over the window, the devices and the clock.
    const std::string cause = live->reload_cause();
    auto prepared = live->take_prepared();
    if (!prepared.ok()) {
      std::cerr << "error: " << prepared.error << " (reload refused; the running show goes on)" << std::endl;
      live->reloaded(cause, prepared.error);
      continue;
    }
    service.reloading();
    auto next = LiveShow::take_over(std::move(*prepared.value), live.get());
    if (!next.ok()) {
      std::cerr << "error: " << next.error << " (reload refused)" << std::endl;
      if (live->released()) return kExitBadInput;  // it had let go of its devices and window
      live->reloaded(cause, next.error);
      continue;
    }
    live = std::move(*next.value);
    if (service.active()) live->set_service(&service);
    if (live->restarted().empty())
      std::cerr << "reloaded " << a.show << " (" << cause << ") at frame " << live->frames()
                << ": the clock, the devices and the outputs go on" << std::endl;
    else
      std::cerr << "reloaded " << a.show << " (" << cause << "): " << live->restarted()
                << " changed, so the devices, the window and the outputs start over" << std::endl;
    if (!live->kept().empty() && live->kept().size() < live->actors().size()) {  // (a cast: who was prepared again)
      std::string kept;
      for (const std::string& n : live->kept()) kept += (kept.empty() ? "" : ", ") + n;
      std::cerr << "  unchanged, kept as loaded: " << kept << std::endl;
    }
    live->reloaded(cause);  // (last: what the swap allocated, saying so included, is counted apart up to here)
  }
}

}  // namespace mar
