#include "app/live.h"
#include "app/simulate.h"

#include "geom/polygon.h"

#include "character/color.h"
#include "render/image.h"

#include <SDL.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <thread>

namespace mar {
namespace {

AllocationCounter g_counter = nullptr;
uint64_t allocations() { return g_counter ? g_counter() : 0; }

double now_us() {
  return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

bool display_present() {
  const char* x = std::getenv("DISPLAY");
  const char* wl = std::getenv("WAYLAND_DISPLAY");
  return (x && *x) || (wl && *wl);
}

// Recording format 02: the magic, then records: wire (type 1: time, source, kind, size,
// bytes), frame marker (2: time, iterations), device (3: source, length, the serialized
// DecoderConfig of a connection — before that connection's first wire record).
constexpr char kMagic[8] = {'M', 'A', 'R', 'R', 'E', 'C', '0', '2'};
constexpr uint8_t kRecWire = 1, kRecFrame = 2, kRecDevice = 3;

// Recording writes go to a 1 MiB stdio buffer without taking the FILE lock (only this
// thread uses the file); the buffer is written out when full, which is the one place a
// recorded show touches the disk inside a frame.
void put(const void* p, size_t n, std::FILE* f) { fwrite_unlocked(p, 1, n, f); }

}  // namespace

void set_allocation_counter(AllocationCounter f) { g_counter = f; }

LiveShow::~LiveShow() {
  if (simulation_) simulation_->stop();
  devices_.reset();
  if (record_) std::fclose(record_);
  if (replay_) std::fclose(replay_);
}

Result<std::unique_ptr<LiveShow>> LiveShow::load(const std::string& path, const RunOptions& o) {
  using R = Result<std::unique_ptr<LiveShow>>;
  auto header = load_show_header(path);
  if (!header.ok()) return R::failure(header.error);
  auto puppet = load_puppet(header.value->character, header.value->rig);
  if (!puppet.ok()) return R::failure(puppet.error);
  std::unique_ptr<LiveShow> s(new LiveShow());
  s->opt_ = o;
  s->puppet_ = std::move(*puppet.value);
  Puppet& p = *s->puppet_;
  std::vector<std::string> names;
  for (const auto& h : p.rig.handles) names.push_back(h.name);
  const std::vector<Vec2> rest = p.rest_targets();
  const Bounds bb = p.character.bounds();
  const double diag = std::hypot(bb.hi.x() - bb.lo.x(), bb.hi.y() - bb.lo.y());
  auto show = load_show(path, names, rest, diag);
  if (!show.ok()) return R::failure(show.error);
  s->show_ = std::move(*show.value);
  ShowConfig& sh = s->show_;
  s->period_s_ = 1.0 / (o.rate > 0 ? o.rate : sh.rate_hz);
  s->iterations_ = sh.iterations;
  s->hud_ = sh.hud;
  if (auto c = parse_color(sh.background)) s->background_ = *c;

  Mapping& m = s->mapping_;
  m.set_handles(names, rest);
  m.set_iterations(sh.iterations, sh.min_iterations, 200);
  m.set_weights(p.rig.w_rigidity, p.rig.w_coupling, p.rig.w_position);
  for (auto& g : sh.groups) m.add_group(g);
  for (auto& po : sh.poses) m.add_pose(po);
  for (Binding b : sh.bindings) {
    if (b.control.kind == ControlSpec::Pointer && b.tf.area[0] == 0 && b.tf.area[2] == 1) {
      // Default pointer area: the tablet covers the character's bounding box.
      b.tf.area[0] = bb.lo.x();
      b.tf.area[1] = bb.lo.y();
      b.tf.area[2] = bb.hi.x();
      b.tf.area[3] = bb.hi.y();
    }
    m.add_binding(b);
  }

  for (size_t i = 0; i < sh.devices.size(); ++i) {
    ShowDevice& d = sh.devices[i];
    const bool hardware = d.type != "sim";
    s->has_hardware_ = s->has_hardware_ || hardware;
    if (d.sim.empty() || (hardware && !o.simulate)) continue;
    if (d.descriptor_in_corpus && !std::filesystem::exists(d.descriptor)) {
      // The shared corpus is test material that may not be on this machine: the show still
      // runs, with the simulator's built-in descriptor.
      if (!o.quiet)
        std::cerr << "warning: " << sh.path << ":" << d.line << ": device '" << d.name << "': " << d.descriptor
                  << " not found (set MARIONETTE_CORPUS_DIR); using the built-in descriptor\n";
      d.descriptor.clear();
    }
    auto dev = make_sim_device(d.sim, d.descriptor, d.bounce_ms, d.seed);
    if (!dev.ok()) return R::failure(sh.path + ":" + std::to_string(d.line) + ": device '" + d.name + "': " + dev.error);
    if (auto ok = (*dev.value)->load_script(d.script); !ok.ok())
      return R::failure(sh.path + ":" + std::to_string(d.line) + ": device '" + d.name + "' script " + ok.error);
    s->sims_.resize(sh.devices.size());
    s->sims_[i] = std::move(*dev.value);
  }
  s->wires_.resize(4096);
  s->events_.resize(4096);
  s->targets_ = rest;
  s->targets_.push_back(Vec2::Zero());  // the grab handle's target (used while grabbing)
  s->replay_pending_.reserve(1 << 16);
  s->replay_decoders_.resize(sh.devices.size());
  std::string err;
  if (!s->open_output(&err)) return R::failure(err);
  // After the window: mouse and touch sources read over it.
  if (o.replay_path.empty()) err = s->open_devices();
  if (!err.empty()) return R::failure(err);
  return R::success(std::move(s));
}

bool LiveShow::open_output(std::string* err) {
  const ShowConfig& sh = show_;
  if (!opt_.headless && display_present()) {
    auto w = Canvas::window("marionette - " + std::filesystem::path(sh.path).stem().string(), sh.width, sh.height,
                            sh.fullscreen, false);
    if (w.ok()) canvas_ = std::move(*w.value);
    else if (!opt_.quiet) std::cerr << "warning: no window (" << w.error << "); running headless\n";
  }
  if (!canvas_) {
    if (!opt_.headless && opt_.dump_dir.empty() && opt_.replay_path.empty()) {
      // Asked for a window but there is no display: run headless and keep every 10th
      // frame so the performance can still be seen.
      opt_.dump_dir = "marionette-frames";
      opt_.every = 10;
      if (!opt_.quiet) std::cout << "no display found (DISPLAY/WAYLAND_DISPLAY unset): running headless" << std::endl;
    }
    opt_.headless = true;
    auto c = Canvas::offscreen(sh.width, sh.height);
    if (!c.ok()) {
      *err = c.error;
      return false;
    }
    canvas_ = std::move(*c.value);
  }
  view_ = fit_view(puppet_->character.width, puppet_->character.height, canvas_->width(), canvas_->height(), 16);
  if (!opt_.record_path.empty()) {
    record_ = std::fopen(opt_.record_path.c_str(), "wb");
    if (!record_) {
      *err = opt_.record_path + ": cannot write the recording";
      return false;
    }
    std::setvbuf(record_, nullptr, _IOFBF, 1 << 20);
    std::fwrite(kMagic, 1, 8, record_);
  }
  if (!opt_.replay_path.empty()) {
    replay_ = std::fopen(opt_.replay_path.c_str(), "rb");
    char magic[8] = {};
    if (!replay_ || std::fread(magic, 1, 8, replay_) != 8 || std::memcmp(magic, kMagic, 8) != 0) {
      *err = opt_.replay_path + ": not a marionette recording";
      return false;
    }
  }
  if (!opt_.dump_dir.empty()) std::filesystem::create_directories(opt_.dump_dir);
  return true;
}

void LiveShow::record_wire(const WireRecord& r) {
  if (!record_) return;
  const uint8_t type = kRecWire;
  put(&type, 1, record_);
  put(&r.t_ns, 8, record_);
  put(&r.source, 2, record_);
  put(&r.kind, 1, record_);
  put(&r.size, 1, record_);
  put(r.data, r.size, record_);
}

void LiveShow::record_device(uint16_t source, std::span<const uint8_t> description) {
  if (!record_) return;
  const uint8_t type = kRecDevice;
  const uint32_t n = uint32_t(description.size());
  put(&type, 1, record_);
  put(&source, 2, record_);
  put(&n, 4, record_);
  put(description.data(), n, record_);
}

bool LiveShow::replay_next(int64_t& t_ns, int& iterations) {
  // Reads wire records up to the next frame marker into replay_pending_.
  replay_pending_.clear();
  for (;;) {
    uint8_t type = 0;
    if (std::fread(&type, 1, 1, replay_) != 1) return false;
    if (type == kRecFrame) {
      uint16_t it = 0;
      if (std::fread(&t_ns, 8, 1, replay_) != 1 || std::fread(&it, 2, 1, replay_) != 1) return false;
      iterations = it;
      return true;
    }
    if (type == kRecDevice) {
      // A connection's decoder, made from the description the live show recorded.
      uint16_t src = 0;
      uint32_t n = 0;
      if (std::fread(&src, 2, 1, replay_) != 1 || std::fread(&n, 4, 1, replay_) != 1 || n > (1u << 20)) return false;
      std::vector<uint8_t> bytes(n);
      if (std::fread(bytes.data(), 1, n, replay_) != n) return false;
      auto cfg = DecoderConfig::parse(bytes);
      std::string err;
      std::unique_ptr<Decoder> dec = cfg.ok() ? make_decoder(*cfg.value, src, &err) : nullptr;
      if (!dec && !opt_.quiet)
        std::cerr << "warning: " << opt_.replay_path << ": device " << src << ": " << (cfg.ok() ? err : cfg.error)
                  << " (its records are dropped)\n";
      if (src < replay_decoders_.size()) replay_decoders_[src] = std::move(dec);
      continue;
    }
    WireRecord r;
    if (type != kRecWire || std::fread(&r.t_ns, 8, 1, replay_) != 1 || std::fread(&r.source, 2, 1, replay_) != 1 ||
        std::fread(&r.kind, 1, 1, replay_) != 1 || std::fread(&r.size, 1, 1, replay_) != 1 ||
        r.size > WireRecord::kMax || std::fread(r.data, 1, r.size, replay_) != r.size)
      return false;
    replay_pending_.push_back(r);
  }
}

void LiveShow::drain(int64_t t_ns) {
  // One input path: every source's wire records (hardware, simulated or recorded) are
  // recorded as read and decoded by their connection's decoder.
  EventSink ev{events_.data(), events_.size()};
  if (replay_) {
    for (const WireRecord& r : replay_pending_) {
      if (r.source < replay_decoders_.size() && replay_decoders_[r.source]) replay_decoders_[r.source]->feed(r, ev);
      else ++dropped_events_;  // a record with no device description before it
    }
    for (auto& d : replay_decoders_)
      if (d) d->settle(t_ns, ev);
  } else {
    WireSink ws{wires_.data(), wires_.size()};
    devices_->poll(t_ns, ws);
    dropped_records_ += ws.dropped;
    for (size_t i = 0; i < devices_->size(); ++i)
      if (devices_->take_connected(i)) record_device(devices_->backend(i).source(), devices_->description(i));
    for (size_t k = 0; k < ws.n; ++k) {
      record_wire(wires_[k]);
      devices_->decode(wires_[k], ev);
    }
    devices_->settle(t_ns, ev);
  }
  n_events_ = ev.n;
  dropped_events_ += ev.dropped;
  if (!replay_) feedback();
}

void LiveShow::regrab(bool down) {
  // Grab-and-drag: the character point nearest the pen becomes a temporary handle, added to
  // the factorised system by a rank-2 update (no re-factorisation, no allocation).
  Puppet& p = *puppet_;
  const double t0 = now_us();
  grab_handle_ = -1;
  if (down) {
    const Vec2 g = mapping_.grab_point();
    // Near an existing handle, the pen takes that handle over (two handles side by side
    // would pull against each other); elsewhere the nearest point becomes a new handle.
    double nearest = INFINITY;
    for (size_t h = 0; h < p.solver->handle_count(); ++h) {
      const Vec2 at = p.solver->handle_point(h);
      if (double d = (at - g).norm(); d < nearest) {
        nearest = d;
        grab_handle_ = int(h);
        grab_offset_ = at - g;
      }
    }
    if (nearest > 0.05 * p.diagonal) grab_handle_ = -1;
  }
  if (down && grab_handle_ >= 0) {
    p.solver->release();
  } else if (down) {
    const Vec2 g = mapping_.grab_point();
    double best = INFINITY;
    Vec2 rest = Vec2::Zero();
    for (size_t s = 0; s < p.shapes.size(); ++s)
      for (size_t k = 0; k < p.shapes[s].size(); ++k)
        if (double d = (p.shapes[s][k] - g).squaredNorm(); d < best) {
          best = d;
          rest = p.character.shapes[s].points[k];
        }
    p.solver->grab(rest);
    targets_.back() = g;
  } else {
    p.solver->release();
  }
  grab_us_.add(now_us() - t0);
  ++grabs_;
  grabbing_ = down;
}

void LiveShow::refactor() {
  // New solver weights from a control: the system matrix changes, so it is factorised
  // again (measured: refactor_us; Eigen's factorisation allocates, counted on its own).
  Puppet& p = *puppet_;
  const double t0 = now_us();
  const uint64_t a0 = allocations();
  const double* w = mapping_.weights();
  const bool grabbing = grabbing_;
  SolverWeights sw = p.weights();
  sw.rigidity = w[0];
  sw.coupling = w[1];
  sw.position = w[2];
  p.solver->set_weights(sw, nullptr);
  grabbing_ = false;
  if (grabbing) regrab(true);
  refactor_us_.add(now_us() - t0);
  ++refactorizations_;
  refactor_allocs_ += allocations() - a0;
  alloc_base_ += allocations() - a0;
}

void LiveShow::frame(int64_t t_ns) {
  Puppet& p = *puppet_;
  const double a0 = now_us();
  if (frames_ == opt_.warmup) alloc_base_ = allocations();
  drain(t_ns);
  const double a1 = now_us();
  for (size_t i = 0; i < n_events_; ++i) mapping_.apply(events_[i]);
  const double dt = frames_ ? double(t_ns - last_t_) * 1e-9 : 0;
  last_t_ = t_ns;
  mapping_.update(dt);
  // Budget governor: drop an iteration (never below the floor) when the last frame used
  // more than 80% of the budget, give it back below 40%; replays use the recorded count.
  const int want = mapping_.iterations();
  if (!replay_) {
    const double budget_ms = period_s_ * 1e3;
    if (iterations_ > want) iterations_ = want;
    if (last_compute_ms_ > 0.8 * budget_ms && iterations_ > show_.min_iterations) {
      --iterations_;
      ++governor_steps_;
    } else if (last_compute_ms_ < 0.4 * budget_ms && iterations_ < want) {
      ++iterations_;
    }
  }
  if (mapping_.weights_changed()) refactor();
  if (mapping_.grab_active() != grabbing_) regrab(mapping_.grab_active());
  const auto mt = mapping_.targets();
  for (size_t i = 0; i < mt.size(); ++i) targets_[i] = mt[i];
  const bool extra = grabbing_ && grab_handle_ < 0;
  if (extra) targets_.back() = mapping_.grab_point();
  if (grabbing_ && grab_handle_ >= 0) targets_[size_t(grab_handle_)] = mapping_.grab_point() + grab_offset_;
  const double a2 = now_us();
  p.solver->solve(std::span<const Vec2>(targets_.data(), extra ? targets_.size() : targets_.size() - 1), iterations_);
  const double a3 = now_us();
  p.reconstruct();
  // Pose quality: the worst part's distortion (RMS residual of its best rigid fit to its
  // rest shape), in thousandths of a percent of the character's height.
  double worst = 0;
  for (size_t k = 0; k < p.shapes.size(); ++k) {
    worst = std::max(worst, rigid_fit_rms(p.character.shapes[k].points, p.shapes[k]));
  }
  quality_.add(worst * 100.0 / std::max(1e-9, p.character.height) * 1000.0);
  canvas_->clear(background_);
  list_.clear();
  build_draw_list(p.character, p.mesh, p.shapes, view_, 0.3, list_);
  canvas_->draw(list_);
  if (hud_ && canvas_->is_window()) draw_hud();
  const double a4 = now_us();
  canvas_->present();
  const double a5 = now_us();
  if (!opt_.dump_dir.empty() && frames_ % std::max(1, opt_.every) == 0) {
    // PNG export allocates and writes a file: it is left out of the frame's time and of
    // the allocation count (a debugging aid, not part of the show).
    const uint64_t before = allocations();
    const auto px = canvas_->read_premultiplied();
    char name[64];
    std::snprintf(name, sizeof name, "frame_%06ld.png", frames_);
    write_png((std::filesystem::path(opt_.dump_dir) / name).string(),
              downsample_premultiplied(px.data(), canvas_->width(), canvas_->height(), 1));
    alloc_base_ += allocations() - before;
  }
  // run_hash: FNV-1a over every frame's deformed vertices.
  for (const Points& s : p.shapes)
    for (const Vec2& v : s) {
      const double xy[2] = {v.x(), v.y()};
      const auto* b = reinterpret_cast<const uint8_t*>(xy);
      for (size_t k = 0; k < sizeof xy; ++k) hash_ = (hash_ ^ b[k]) * 1099511628211ull;
    }
  if (record_) {
    const uint8_t type = kRecFrame;
    const uint16_t it = uint16_t(iterations_);
    put(&type, 1, record_);
    put(&t_ns, 8, record_);
    put(&it, 2, record_);
  }
  const double compute_us = a5 - a0;
  for (size_t i = 0; i < n_events_; ++i) st_.latency.add(double(t_ns - events_[i].t_ns) * 1e-3 + compute_us);
  st_.drain.add(a1 - a0);
  st_.map.add(a2 - a1);
  st_.solve.add(a3 - a2);
  st_.render.add(a4 - a3);
  st_.present.add(a5 - a4);
  st_.frame.add(compute_us);
  last_compute_ms_ = compute_us * 1e-3;
  if (compute_us > period_s_ * 1e6) ++overruns_;
  iter_sum_ += iterations_;
  iter_min_ = std::min(iter_min_, iterations_);
  iter_max_ = std::max(iter_max_, iterations_);
  ++frames_;
  if (frames_ > opt_.warmup) allocs_ = allocations() - alloc_base_;
}

void LiveShow::draw_hud() {
  SDL_Renderer* r = canvas_->renderer();
  const double budget = period_s_ * 1e6, used = last_compute_ms_ * 1e3;
  const int w = canvas_->width() - 20;
  SDL_SetRenderDrawBlendMode(r, SDL_BLENDMODE_BLEND);
  SDL_SetRenderDrawColor(r, 0, 0, 0, 90);
  SDL_Rect bg{10, 10, w, 14};
  SDL_RenderFillRect(r, &bg);
  const double share = std::min(1.0, used / budget);
  SDL_SetRenderDrawColor(r, share < 0.5 ? 60 : 230, share < 0.8 ? 180 : 60, 60, 220);
  SDL_Rect bar{10, 10, int(w * share), 14};
  SDL_RenderFillRect(r, &bar);
  for (size_t i = 0; i < show_.devices.size(); ++i) {
    // Device status: green connected (or simulated), amber waiting, red unplugged or
    // denied, grey unavailable.
    const DeviceState st = devices_ ? devices_->state(i) : DeviceState::Connected;
    static constexpr uint8_t kColour[][3] = {{230, 170, 40},   // waiting
                                             {60, 180, 60},    // connected
                                             {220, 50, 50},    // unplugged
                                             {220, 50, 50},    // permission denied
                                             {140, 140, 140}};  // unavailable
    const uint8_t* c = kColour[size_t(st)];
    SDL_SetRenderDrawColor(r, c[0], c[1], c[2], 230);
    SDL_Rect box{10 + int(i) * 18, 30, 14, 14};
    SDL_RenderFillRect(r, &box);
  }
}

int LiveShow::run() {
  const bool learn = !opt_.learn.empty();
  int64_t end_ns = 0;
  bool scripted = false;
  for (const auto& s : sims_)
    if (s) {
      end_ns = std::max(end_ns, s->end_ns());
      scripted = true;
    }
  long limit = opt_.frames;
  // Headless: until the scripts end (+ half a second for the last events to arrive from
  // the bench); a headless show of real hardware alone runs until interrupted.
  if (limit < 0 && opt_.headless && !replay_ && scripted)
    limit = long(std::ceil((double(end_ns) * 1e-9 + (has_hardware_ ? 0.5 : 0)) / period_s_)) + 1;
  if (!opt_.quiet)
    std::cout << (replay_ ? "replaying " : "running ") << show_.path << (opt_.headless ? " headless" : " in a window")
              << " at " << std::lround(1.0 / period_s_) << " Hz" << (limit > 0 ? ", " + std::to_string(limit) + " frames" : "")
              << std::endl;
  const auto start = std::chrono::steady_clock::now();
  if (!has_hardware_) epoch_ns_ = monotonic_ns();  // with hardware: set when the devices opened
  install_quit_handler();
  while (!quit_ && !stop_ && !quit_requested() && (limit < 0 || frames_ < limit)) {
    int64_t t = int64_t(std::llround(double(frames_) * period_s_ * 1e9));
    if (replay_) {
      int it = iterations_;
      if (!replay_next(t, it)) break;
      iterations_ = it;
    } else if (realtime()) {
      t = monotonic_ns() - epoch_ns_;  // the clock device timestamps are on
    }
    if (canvas_->is_window()) {
      SDL_Event ev;
      while (SDL_PollEvent(&ev)) {
        if (ev.type == SDL_QUIT) quit_ = true;
        if (ev.type == SDL_KEYDOWN) {
          const auto k = ev.key.keysym.sym;
          if (k == SDLK_ESCAPE || k == SDLK_q) quit_ = true;
          if (k == SDLK_h) hud_ = !hud_;
        }
      }
    }
    frame(t);
    if (learn) {
      for (size_t i = 0; i < n_events_ && !learned_; ++i) {
        const Event& e = events_[i];
        // The control that moved, in the grammar show files use (format_control prints what
        // parse_control reads).
        ControlSpec spec;
        switch (e.kind) {
          case ControlKind::MidiCC: spec.kind = ControlSpec::CC; break;
          case ControlKind::MidiNoteOn: spec.kind = ControlSpec::Note; break;
          case ControlKind::MidiPitchBend: spec.kind = ControlSpec::PitchBend; break;
          case ControlKind::EncoderDelta:
            spec.kind = show_.devices[e.source].sim == "knob_box" || show_.devices[e.source].type == "gpio" ? ControlSpec::Encoder
                                                                                                             : ControlSpec::Hid;
            break;
          case ControlKind::Button: spec.kind = ControlSpec::GpioButton; break;
          case ControlKind::HidValue: spec.kind = ControlSpec::Hid; break;
          default: continue;
        }
        spec.number = e.number;
        if (e.kind == ControlKind::MidiCC || e.kind == ControlKind::MidiNoteOn || e.kind == ControlKind::MidiPitchBend)
          spec.channel = e.channel;
        const std::string control = format_control(spec);
        if (std::string err = append_binding(show_.path, show_.devices[e.source].name, control, opt_.learn); !err.empty()) {
          std::cerr << "error: " << err << "\n";
          return 1;
        }
        std::cout << "learned: " << show_.devices[e.source].name << " '" << control << "' -> " << opt_.learn
                  << " (written to " << show_.path << ")" << std::endl;
        learned_ = true;
      }
      if (learned_) break;
    }
    if (realtime() && !replay_) {
      const auto next = start + std::chrono::nanoseconds(int64_t(double(frames_) * period_s_ * 1e9));
      std::this_thread::sleep_until(next);  // frame pacing, outside the frame
    }
  }
  if (record_) std::fflush(record_);
  if (learn && !learned_) {
    std::cerr << "error: no control moved; nothing learned for " << opt_.learn << "\n";
    return 1;
  }
  if (!opt_.quiet) {
    std::cout << frames_ << " frames, frame p50 " << std::lround(st_.frame.quantile(0.5)) << " us, p99 "
              << std::lround(st_.frame.quantile(0.99)) << " us, overruns " << overruns_ << ", run_hash " << std::hex
              << hash_ << std::dec << std::endl;
    if (!opt_.dump_dir.empty()) std::cout << "frames written to " << opt_.dump_dir << std::endl;
  }
  if (!opt_.stats_path.empty()) {
    std::FILE* f = std::fopen(opt_.stats_path.c_str(), "w");
    if (!f) {
      std::cerr << "error: " << opt_.stats_path << ": cannot write stats\n";
      return 1;
    }
    const std::string j = stats_json();
    std::fwrite(j.data(), 1, j.size(), f);
    std::fclose(f);
  }
  return 0;
}

}  // namespace mar
