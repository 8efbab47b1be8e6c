#include "app/live.h"

#include "app/keys.h"

#include "app/loop/hud.h"
#include "app/loop/learn.h"
#include "app/simulate.h"
#include "character/color.h"
#include "geom/polygon.h"
#include "base/read_file.h"
#include "render/image.h"

#include <SDL.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <thread>

namespace mar {
namespace {

AllocationCounter g_counter = nullptr;
uint64_t allocations() { return g_counter ? g_counter() : 0; }

double now_us() {
  return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

void set_allocation_counter(AllocationCounter f) { g_counter = f; }
uint64_t LiveShow::allocation_count() { return allocations(); }

LiveShow::~LiveShow() {
  if (simulation_) simulation_->stop();
  devices_.reset();
  // (the outputs' threads may still read the cast's drawings: they finish before the cast goes)
  outputs_.reset();
  recorder_.reset();
}


std::string LiveShow::validate(const std::string& path) {
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  auto s = prepare(path, o);  // everything load() reads and checks, with no device or window
  return s.ok() ? std::string() : s.error;
}


Result<std::unique_ptr<LiveShow>> LiveShow::load(const std::string& path, const RunOptions& o, LiveShow* previous) {
  auto s = prepare(path, o, previous ? previous->keepable() : std::vector<KeptPuppet>{});
  if (!s.ok()) return s;
  return take_over(std::move(*s.value), previous);
}

Result<std::unique_ptr<LiveShow>> LiveShow::take_over(std::unique_ptr<LiveShow> s, LiveShow* previous) {
  using R = Result<std::unique_ptr<LiveShow>>;
  if (previous) {
    s->restarted_ = s->keeps(*previous);  // a reload: what it cannot keep (empty: all)
    for (auto& a : s->actors_)  // the puppets it kept (unchanged files) go on as they are posed
      for (auto& old : previous->actors_)
        if (a->shares_puppet_with(*old)) a->take_puppet_from(*old);
  }
  const bool keep = previous && s->restarted_.empty();
  if (keep) {  // everything that could fail has: take over the running show's clock and devices
    s->adopt(*previous);
    return R::success(std::move(s));
  }
  if (previous) previous->release();
  std::string err;
  if (!s->open_output(&err)) return R::failure(err);
  s->pacer_ = Pacer(s->pacer_.period_s(), s->realtime());  // open_output decides window or headless
  // After the window: mouse and touch sources read over it.
  if (s->opt_.replay_path.empty()) err = s->open_devices();
  if (!err.empty()) return R::failure(err);
  return R::success(std::move(s));
}

bool LiveShow::open_output(std::string* err) {
  const ShowConfig& sh = show_;
  // The canvas: [output]'s size, else the window's; at N x with --supersample N (dumps are
  // box-filtered back down).
  const auto [canvas_w, canvas_h] = canvas_size(opt_, sh);
  const int ss = std::clamp(opt_.supersample, 1, 8);
  if (!opt_.headless && display_named()) {
    WindowOptions wo;
    wo.title = "marionette - " + std::filesystem::path(sh.path).stem().string();
    wo.width = sh.width;
    wo.height = sh.height;
    wo.fullscreen = sh.fullscreen || sh.kiosk.enabled;
    wo.screen = sh.kiosk.enabled ? sh.kiosk.display : sh.screen;
    wo.screen_name = sh.kiosk.enabled ? std::string() : sh.screen_name;
    wo.transparent = background_.a < 1;
    wo.vsync = sh.vsync;
    // A kiosk may start before its display answers (an X server still starting at boot).
    wo.display_wait_s = sh.kiosk.enabled ? 10.0 : 1.0;
    // Blur, shadows, clip paths and masks are composited by the software rasterizer: a character
    // that has them is drawn there and uploaded, in a GPU window too (the GPU multiplies a
    // group's opacity into its shapes).
    std::string soft;
    for (const auto& a : actors_)
      for (const Composite& c : a->puppet().character.composites)
        if (c.blur > 0 || c.shadow || c.offset.squaredNorm() > 0 || !c.clip.empty() || !c.mask.empty()) {
          wo.gpu = false;
          soft = a->puppet().character.source;
        }
    if (!wo.gpu && !opt_.quiet) std::cout << "drawn in software: " << soft << " has blur, shadows, clip paths or masks" << std::endl;
    std::string note;
    auto w = Canvas::window(wo, canvas_w * ss, canvas_h * ss, &note);
    if (!note.empty() && !opt_.quiet) std::cerr << "warning: " << sh.path << ": [display] " << note << "\n";
    if (w.ok()) {
      canvas_ = std::move(*w.value);
      if (sh.kiosk.enabled) SDL_ShowCursor(SDL_DISABLE);
      hud_panel_ = std::make_unique<Hud>(show_);
      if (const std::string e = hud_panel_->load_font(canvas_->window_renderer()); !e.empty() && !opt_.quiet)
        std::cerr << "warning: the HUD has no text: " << e << "\n";
    } else if (sh.kiosk.enabled) {
      // A kiosk with no screen shows no one anything, and headless it would fill its disk with
      // frames for weeks: it stops, and its service manager starts it again.
      *err = sh.path + ": a kiosk needs a screen, and there is none (" + w.error + ")";
      return false;
    } else if (!opt_.quiet) {
      std::cerr << "warning: no window (" << w.error << "); running headless\n";
    }
  }
  if (!canvas_) {
    if (!opt_.headless && sh.kiosk.enabled) {
      *err = sh.path + ": a kiosk needs a screen, and there is none (DISPLAY, WAYLAND_DISPLAY and SDL_VIDEODRIVER are unset)";
      return false;
    }
    if (!opt_.headless && opt_.dump_dir.empty() && opt_.replay_path.empty()) {
      // Asked for a window but there is none: run headless and keep every 10th frame so the
      // performance can still be seen.
      opt_.dump_dir = "marionette-frames";
      opt_.every = 10;
      if (!opt_.quiet)
        std::cout << (display_named() ? "no window" : "no display found (DISPLAY/WAYLAND_DISPLAY unset)")
                  << ": running headless, every 10th frame written to marionette-frames/" << std::endl;
    }
    opt_.headless = true;
    auto c = Canvas::offscreen(canvas_w * ss, canvas_h * ss);
    if (!c.ok()) {
      *err = c.error;
      return false;
    }
    canvas_ = std::move(*c.value);
  }
  place_cast(canvas_->width(), canvas_->height(), ss);
  stage_.place(canvas_->width(), canvas_->height(), ss);
  use_backdrop();
  canvas_->set_antialias(!opt_.aliased);
  reserve_layers();
  if (!opt_.replay_path.empty()) {
    auto r = Playback::open(opt_.replay_path);
    if (!r.ok()) {
      *err = r.error;
      return false;
    }
    if ((*r.value)->identity() != show_identity(show_) && !opt_.force) {
      *err = opt_.replay_path + ": a take of another show (its devices differ from " + show_.path +
             "'s); --force plays it anyway";
      return false;
    }
    playback_ = std::move(*r.value);
  }
  if (!opt_.dump_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(opt_.dump_dir, ec);
    if (ec || !std::filesystem::is_directory(opt_.dump_dir)) {
      *err = opt_.dump_dir + ": cannot make the folder for the frames (" + (ec ? ec.message() : "not a folder") + ")";
      return false;
    }
  }
  return true;
}

// ---- the stages ----------------------------------------------------------------------

void LiveShow::inputs(int64_t t_ns) {
  // One input path: every source's wire records (hardware, simulated or recorded) are
  // recorded as read and decoded by their connection's decoder.
  EventSink ev{events_.data(), events_.size()};
  if (playback_) {
    for (const WireRecord& r : replay_wires_) {
      if (r.source < replay_decoders_.size() && replay_decoders_[r.source]) replay_decoders_[r.source]->feed(r, ev);
      else ++dropped_records_;  // a record with no device description before it
    }
    for (auto& d : replay_decoders_)
      if (d) d->settle(t_ns, ev);
  } else {
    WireSink ws{wires_.data(), wires_.size()};
    devices_->poll(t_ns, ws);
    dropped_records_ += ws.dropped;
    for (size_t i = 0; i < devices_->size(); ++i)
      if (recorder_ && devices_->take_connected(i)) recorder_->device(devices_->backend(i).source(), devices_->description(i));
    for (size_t k = 0; k < ws.n; ++k) {
      if (recorder_) recorder_->wire(wires_[k]);
      devices_->decode(wires_[k], ev);
    }
    devices_->settle(t_ns, ev);
  }
  n_events_ = ev.n;
  dropped_events_ += ev.dropped;
  for (size_t i = 0; i < n_events_; ++i)
    if (events_[i].source < last_events_.size()) last_events_[events_[i].source] = events_[i];
  if (!playback_) feedback();
}

void LiveShow::map(int64_t t_ns) {
  bool input = false;  // a visitor moved a bound control (what keeps the attract away)
  for (size_t i = 0; i < n_events_; ++i) {
    if (!leds_.empty() && leds_.echo(events_[i], t_ns)) continue;  // a controller sending our lights back
    input = mapping_.apply(events_[i]) || input;
    if (events_[i].kind == ControlKind::ClockPhase) beat_.event(events_[i]);  // MIDI clock: the music time
  }
  const double dt = stats_.frames ? double(t_ns - last_t_) * 1e-9 : 0;
  beat_.step(t_ns, dt);
  dt_ = dt;
  last_t_ = t_ns;
  mapping_.update(dt);
  if (mapping_.take_settings_changed()) apply_settings();
  if (attract_) attract_->step(dt, input);
  // Swaps and triggers follow whichever side of the crossfade is stronger.
  const bool by_attract = attract_ && attract_->weight() >= 0.5;
  Mapping* attract_mapping = attract_ ? &attract_->mapping() : nullptr;
  const bool attract_changed = attract_mapping && attract_mapping->take_shown_changed();
  const bool live_changed = mapping_.take_shown_changed();
  if (live_changed || (by_attract && attract_changed) || by_attract != shown_by_attract_) {
    // a swap or a trigger: what shows changes, the pose does not
    const Mapping& by = by_attract ? *attract_mapping : mapping_;
    shown_by_attract_ = by_attract;
    for (size_t i = 0; i < swap_members_.size(); ++i) swap_members_[i] = by.swap_member(i);
    for (size_t i = 0; i < triggers_on_.size(); ++i) triggers_on_[i] = by.trigger_on(i);
    for (auto& a : actors_) {
      const Actor::Ranges& r = a->ranges();
      a->puppet().show(std::span<const int>(swap_members_).subspan(r.swap0, r.swaps),
                       std::span<const char>(triggers_on_).subspan(r.trigger0, r.triggers));
    }
  }
  // Iterations: replays use the recorded counts; on the wall clock the budget governor follows
  // the last frame's cost; on the virtual clock the count is what the show asks for, so a busy
  // machine cannot change what is computed.
  if (playback_) {
  } else if (pacer_.realtime()) {
    governor_.next(int(mapping_.setting(setting_iterations_)), last_compute_ms_, pacer_.period_s() * 1e3);
  } else {
    governor_.force(int(mapping_.setting(setting_iterations_)));
  }
  // The pen: the actor it holds lets go when it comes up or another pen takes over.
  const int want = mapping_.grab_active() ? mapping_.grab_who() : -1;
  if (want != grabbed_) {
    if (grabbed_ >= 0) actors_[size_t(grabbed_)]->set_grab(false, mapping_.grab_point());
    if (want >= 0) actors_[size_t(want)]->set_grab(true, mapping_.grab_point());
    grabbed_ = want;
  }
  const auto mt = mapping_.targets();
  for (size_t i = 0; i < mt.size(); ++i) targets_[i] = mt[i];
  if (attract_ && attract_->shown()) {  // the crossfade: from the visitor's targets to the attract's
    const double w = attract_->weight();
    const auto at = attract_->mapping().targets();
    for (size_t i = 0; i < mt.size(); ++i) targets_[i] += w * (at[i] - mt[i]);
  }
  for (auto& a : actors_) a->apply_grab(mapping_.grab_point(), slice(*a));
  if (!show_.brushes.empty() || !show_.curves.empty()) {  // the brush and the curve: the pen, to its actor (they step in the solve)
    const Mapping::Pen& pen = mapping_.brush();
    for (auto& a : actors_)
      if (a->has_brush() || a->has_curve()) {
        // (before the pen's first event it names no tool: a show of curves alone has no brush 0)
        const bool mine = pen.who == a->ranges().who, tool = pen.brush >= 0;
        const bool brush = mine && tool && !pen.curve && size_t(pen.brush) < show_.brushes.size();
        const bool curve = mine && tool && pen.curve && size_t(pen.brush) < show_.curves.size();
        a->set_pen(pen, brush ? &show_.brushes[size_t(pen.brush)] : nullptr, curve ? &show_.curves[size_t(pen.brush)] : nullptr, dt_);
      }
  }
  if (!leds_.empty() && !playback_) leds_.frame(t_ns, mapping_, swap_members_, triggers_on_, device_states_, lights_);
}

bool LiveShow::pen_over(int who, const Vec2& p) const {
  if (who < 0 || size_t(who) >= actors_.size() || actors_[size_t(who)]->presence() <= 0) return false;
  const Puppet& pp = actors_[size_t(who)]->puppet();
  const double reach = 0.03 * pp.diagonal;
  for (size_t k = 0; k < pp.shapes.size(); ++k) {
    if (!pp.shown[k]) continue;
    if (pp.character.shapes[k].closed() && pp.character.shapes[k].contains(p, pp.shapes[k])) return true;
    for (const Vec2& q : pp.shapes[k])
      if ((q - p).squaredNorm() <= reach * reach) return true;
  }
  return false;
}

void LiveShow::apply_settings() {
  // New solver parameters from a control: the system changes, so it is factorised again
  // (measured: refactor_us; the factorisation allocates, counted on its own).
  for (auto& a : actors_) {
    const double t0 = now_us();
    const uint64_t a0 = allocations();
    if (!a->apply_settings(mapping_)) continue;
    refactor_us_.add(now_us() - t0);
    ++refactorizations_;
    refactor_allocs_ += allocations() - a0;
    alloc_base_ += allocations() - a0;
  }
}

void LiveShow::poses() {
  // Key poses: the morph and blend settings give weights over the keys (a morph from A to B at t
  // puts 1 − t on A and t on B; blends add), the interpolated frame is the base pose, and every
  // handle's target moves by where the base pose has it (the performer's own offsets ride on top).
  idle_.step(dt_, mapping_, beat_.beats());  // idle behaviours: their keys' weights are read below
  // Each key setting's value: the mapping's, crossfaded with the attract's, and an idle
  // behaviour's on top (app/loop/key_poses.h turns them into key weights).
  const double w = attract_ && attract_->shown() ? attract_->weight() : 0.0;
  auto value = [&](int setting) {
    double v = mapping_.setting(setting);
    if (w > 0) v += w * (attract_->mapping().setting(setting) - v);
    return v + idle_.setting_offset(setting);
  };
  Recall r;
  const bool asked = mapping_.take_recall(r);
  for (auto& a : actors_) a->poses(dt_, value, asked && r.who == a->ranges().who ? &r : nullptr, slice(*a));
}

void LiveShow::motion() {
  if (!idle_.empty()) {  // breathing and looking move targets; blinks show over the swaps and triggers
    idle_.apply_targets(targets_, show_.groups, mapping_.pivots());
    if (idle_.has_blinks()) {
      idle_.shown(swap_members_, triggers_on_);
      for (auto& a : actors_) {
        const Actor::Ranges& r = a->ranges();
        a->puppet().show(std::span<const int>(idle_.members()).subspan(r.swap0, r.swaps),
                         std::span<const char>(idle_.triggers()).subspan(r.trigger0, r.triggers));
      }
    }
  }
  auto value = [&](int setting) { return mapping_.setting(setting) + idle_.setting_offset(setting); };
  for (auto& a : actors_) a->motion(dt_, beat_.beats(), value, slice(*a));
}

void LiveShow::solve() {
  // Each actor's solve reads its slice of the targets and writes only its own solver: on the
  // pool, in any order, the same shapes.
  const int iterations = governor_.iterations();
  auto one = [&](size_t i) { actors_[i]->solve(slice(*actors_[i]), iterations); };
  if (pool_) pool_->run(actors_.size(), one);
  else
    for (size_t i = 0; i < actors_.size(); ++i) one(i);
}

void LiveShow::render() {
  // Pose quality: the worst part's distortion in the cast (RMS residual of its best rigid fit
  // to its rest shape), in thousandths of a percent of its character's height.
  auto one = [&](size_t i) { quality_[i] = actors_[i]->reconstruct(); };
  if (pool_) pool_->run(actors_.size(), one);
  else
    for (size_t i = 0; i < actors_.size(); ++i) one(i);
  const auto worst = std::max_element(quality_.begin(), quality_.end());
  quality_pct_ = *worst;
  if (quality_pct_ * 1000.0 > stats_.quality.max() || stats_.quality.count() == 0) {  // (which part, for --stats)
    worst_actor_ = int(worst - quality_.begin());
    worst_shape_ = actors_[size_t(worst_actor_)]->worst_shape();
    worst_frame_ = stats_.frames;
  }
  stats_.quality.add(quality_pct_ * 1000.0);
  if (stage_.copied())
    canvas_->clear_to_underlay();  // the scenery behind, drawn once
  else
    canvas_->clear(background_);
  list_.clear();
  list_.fringe = canvas_->wants_fringe();
  stage_.append_scenery(false, list_);
  for (Actor* a : z_order_) {  // the cast back to front, each with the props it holds
    if (!show_.cast.empty()) a->stage_step(triggers_on_[size_t(stage_trigger0_ + a->ranges().who)] != 0, dt_);
    if (a->presence() <= 0) continue;
    stage_.append_props(*a, false, list_);
    a->draw(list_);
    stage_.append_props(*a, true, list_);
  }
  stage_.append_scenery(true, list_);
  // Warming up, the list makes room for twice what it holds: a pose later in the show may need
  // more triangles than the first ones did (a stroke's round joins change with its angles).
  if (stats_.frames < opt_.warmup) list_.reserve_twice();
  canvas_->draw(list_);
}

void LiveShow::use_backdrop() {
  // (the canvas the show got may differ from the one it was drawn for: then drawn each frame)
  std::vector<uint8_t> px = stage_.take_backdrop();
  stage_.set_copied(!px.empty() && canvas_->set_underlay(std::move(px)));
}

void LiveShow::present() {
  // A window shows the canvas and, over it, the HUD: never in the canvas, dumps or outputs.
  // What the window system and its GPU driver allocate on the way (Xlib and xcb answer SDL's
  // XSync with replies they allocate; Mesa allocates as it takes the texture and the HUD's
  // quads) is counted apart from the frame's own work, which must allocate nothing; the HUD
  // itself allocates nothing (LiveAlloc.TheHudAllocatesNothing).
  const uint64_t before_window = allocations();
  if (canvas_->is_window()) {
    canvas_->compose();
    if (hud_) {
      for (size_t i = 0; i < device_states_.size(); ++i)
        device_states_[i] = devices_ && show_.devices[i].type != "sim" ? devices_->state(i) : DeviceState::Connected;
      const HudFrame f{last_compute_ms_ * 1e3, pacer_.period_s() * 1e6, governor_.iterations(),
                       int(mapping_.setting(setting_iterations_)), quality_pct_, device_states_, last_events_};
      // The character's rest box on the window (through the view and the letterbox): the HUD
      // keeps off it where it can.
      const SDL_Rect shown = canvas_->canvas_rect();
      const double sx = double(shown.w) / std::max(1, canvas_->width()), sy = double(shown.h) / std::max(1, canvas_->height());
      // (a cast: the box round them all and where their drawings cover it, place_cast)
      const bool one = actors_.size() == 1;
      const Vec2 lo = one ? lead().view.apply(lead().rest_bounds.lo) : cast_box_.lo;
      const Vec2 hi = one ? lead().view.apply(lead().rest_bounds.hi) : cast_box_.hi;
      const HudAvoid avoid{shown.x + int(std::min(lo.x(), hi.x()) * sx), shown.y + int(std::min(lo.y(), hi.y()) * sy),
                           int(std::abs(hi.x() - lo.x()) * sx), int(std::abs(hi.y() - lo.y()) * sy), Actor::kCoverCells,
                           one ? lead().rest_cover.data() : cast_cover_.data()};
      hud_panel_->draw(canvas_->window_renderer(), canvas_->window_width(), canvas_->window_height(), f, mapping_, &avoid);
    }
  }
  const uint64_t window_work = allocations() - before_window;
  if (!opt_.screenshot.empty() && canvas_->is_window() && stats_.frames + 1 == opt_.frames) {
    // What the window shows, HUD and letterbox included (a test aid, outside the allocation count).
    const uint64_t before = allocations();
    const auto px = canvas_->read_window();
    write_png(opt_.screenshot, downsample_premultiplied(px.data(), canvas_->window_width(), canvas_->window_height(), 1));
    alloc_base_ += allocations() - before;
  }
  const uint64_t before = allocations();
  canvas_->present();
  if (canvas_->is_window()) {
    const uint64_t n = window_work + allocations() - before;
    if (stats_.frames >= opt_.warmup) present_allocs_ += n;
    alloc_base_ += n;
  }
  if (service_) service_->frame_presented();
}

void LiveShow::finish(int64_t t_ns, double compute_us) {
  for (const auto& a : actors_) stats_.hash.add(a->puppet().shapes);
  int64_t newest_ns = -1;  // this frame's newest input (-1: none), for its age at frame-ready
  for (size_t i = 0; i < n_events_; ++i) newest_ns = std::max(newest_ns, events_[i].t_ns);
  newest_ns_ = newest_ns;
  // Each output on a thread of its own; handing the canvas over is this frame's work. Reading a
  // window's canvas back is SDL's and the driver's (SDL_RenderReadPixels allocates): counted with
  // what presenting allocates, apart from the frame's own.
  const uint64_t before_outputs = allocations();
  if (!show_.cast.empty() && (show_.osc_out.port > 0 || !opt_.dump_poses.empty())) cast_state();  // (what OSC out and a pose dump read)
  compute_us += outputs_->frame(uint64_t(stats_.frames), t_ns, lead().puppet(), *canvas_,
                               {show_.cast.empty() ? lead().key_weights() : std::span<const double>(cast_keys_),
                                std::span<const Vec2>(cast_handles_), cast_shapes_, cast_shown_, swap_members_, triggers_on_, device_states_, compute_us * 1e-3, newest_ns < 0 ? -1 : double(t_ns - newest_ns) * 1e-6 + compute_us * 1e-3});
  if (canvas_->is_window()) {
    const uint64_t n = allocations() - before_outputs;
    if (stats_.frames >= opt_.warmup) present_allocs_ += n;
    alloc_base_ += n;
  }
  if (recorder_) recorder_->frame(t_ns, governor_.iterations());
  for (size_t i = 0; i < n_events_; ++i) stats_.latency.add(double(t_ns - events_[i].t_ns) * 1e-3 + compute_us);
  last_compute_ms_ = compute_us * 1e-3;
  stats_.end_frame(compute_us, pacer_.period_s() * 1e6, governor_.iterations());
  if (stats_.frames > opt_.warmup) allocs_ = allocations() - alloc_base_;
}

void LiveShow::frame(int64_t t_ns) {
  if (stats_.frames == opt_.warmup) alloc_base_ = allocations();
  double at = now_us();
  marks_[0] = at;
  const double start = at;
  auto timed = [&](Stage s, auto&& run) {
    run();
    const double now = now_us();
    stats_.stage[size_t(s)].add(now - at);
    at = now;
  };
  timed(Stage::Inputs, [&] { inputs(t_ns); });
  timed(Stage::Map, [&] { map(t_ns); });
  timed(Stage::Poses, [&] { poses(); });
  timed(Stage::Motion, [&] { motion(); });
  timed(Stage::Solve, [&] { solve(); });
  timed(Stage::Render, [&] { render(); });
  marks_[1] = at;
  timed(Stage::Present, [&] { present(); });
  marks_[2] = at;
  finish(t_ns, at - start);
}

// ---- the run -------------------------------------------------------------------------

void LiveShow::replay_device(uint16_t src, std::span<const uint8_t> description) {
  // A connection's decoder, made from the description the live show recorded.
  auto cfg = DecoderConfig::parse(description);
  std::string err;
  std::unique_ptr<Decoder> dec = cfg.ok() ? make_decoder(*cfg.value, src, &err) : nullptr;
  if (!dec && !opt_.quiet)
    std::cerr << "warning: " << opt_.replay_path << ": device " << src << ": " << (cfg.ok() ? err : cfg.error)
              << " (its records are dropped)\n";
  if (src >= replay_decoders_.size()) return;
  if (const Decoder* old = replay_decoders_[src].get()) {  // a reconnection: keep the counts
    replay_retired_[src].records += old->stats().records;
    replay_retired_[src].events += old->stats().events;
    replay_retired_[src].malformed += old->stats().malformed;
  }
  replay_decoders_[src] = std::move(dec);
}

bool LiveShow::handle_window_events() {
  SDL_Event ev;
  while (SDL_PollEvent(&ev)) {
    if (ev.type == SDL_QUIT && !show_.kiosk.enabled) quit_ = true;  // (a kiosk's window is not closed by a visitor)
    if (ev.type == SDL_KEYDOWN) {
      const WindowKey k = window_key(show_.kiosk, ev.key.keysym.sym, ev.key.keysym.mod);
      if (k == WindowKey::Quit) quit_ = true;
      if (k == WindowKey::ToggleHud) hud_ = !hud_;
    }
  }
  return !quit_;
}

bool LiveShow::learn_from_events() {
  Learned l;
  if (!learn_control(std::span<const Event>(events_.data(), n_events_), show_, l)) return true;
  const std::string& device = show_.devices[l.device].name;
  if (std::string err = append_binding(show_.path, device, l.control, opt_.learn); !err.empty()) {
    std::cerr << "error: " << err << "\n";
    return false;
  }
  std::cout << "learned: " << device << " '" << l.control << "' -> " << opt_.learn << " (written to " << show_.path << ")"
            << std::endl;
  learned_ = true;
  return true;
}

std::string LiveShow::begin() {
  const double period = pacer_.period_s();
  if (!has_hardware_) pacer_.set_epoch(monotonic_ns());  // with hardware: set when the devices opened
  // On the virtual clock the files drop nothing.
  OutputsSpec out;
  out.dump_poses = opt_.dump_poses;
  out.dump_dir = opt_.dump_dir;
  out.every = opt_.every;
  out.video = opt_.video;
  out.codec = opt_.codec;
  out.factor = std::clamp(opt_.supersample, 1, 8);
  out.lossless = !realtime();
  out.pipewire = show_.out_pipewire;
  out.show_path = show_.path;
  out.width = canvas_->width();
  out.height = canvas_->height();
  out.rate = int(std::lround(1.0 / period));
  osc_names(out);
  if (std::string e = outputs_->open(out, outputs_drawing()); !e.empty()) return e;
  if (!opt_.record_path.empty() && !recorder_) {  // (an output: a take that cannot be written is exit 1)
    auto r = Recorder::open(opt_.record_path, show_identity(show_));
    if (!r.ok()) return r.error;
    recorder_ = std::move(*r.value);
  }
  install_quit_handler();
  const bool late_timed = realtime() && !playback_;
  if (late_timed) {  // hot reload on save (the virtual clock's shows run as given, start to end)
    watch_ = std::make_unique<FileWatch>();
    if (const std::string e = watch_->watch(watched_files()); !e.empty()) {
      if (!opt_.quiet) std::cerr << "warning: " << show_.path << ": no reload on save (" << e << ")\n";
      watch_.reset();
    }
  }
  late_.configure(late_timed, (opt_.late_input < 0 ? show_.late_input : opt_.late_input > 0), period * 1e6,
                  show_.late_input_margin_ms * 1e3);
  if (canvas_->is_window()) late_.set_display(canvas_->vsync(), canvas_->refresh_hz());
  pacer_.start();
  started_ = true;
  return {};
}

int64_t LiveShow::scripts_end_ns() const {
  int64_t end_ns = 0;
  for (const auto& s : sims_)
    if (s) end_ns = std::max(end_ns, s->end_ns());
  return end_ns;
}

int LiveShow::run() {
  const bool learn = !opt_.learn.empty();
  const int64_t end_ns = scripts_end_ns();
  bool scripted = false;
  for (const auto& s : sims_) scripted = scripted || s != nullptr;
  long limit = opt_.frames;
  const double period = pacer_.period_s();
  // Headless: until the scripts end (+ half a second for the last events to arrive from
  // the bench); a headless show of real hardware alone runs until interrupted.
  if (limit < 0 && opt_.headless && !playback_ && scripted)
    limit = long(std::ceil((double(end_ns) * 1e-9 + (has_hardware_ ? 0.5 : 0)) / period)) + 1;
  if (!opt_.quiet && !started_)
    std::cout << (playback_ ? "replaying " : "running ") << show_.path
              << (!canvas_->is_window() ? " headless" : show_.kiosk.enabled ? " in a kiosk window" : " in a window")
              << " at " << std::lround(1.0 / period) << " Hz" << (limit > 0 ? ", " + std::to_string(limit) + " frames" : "")
              << std::endl;
  if (!started_) {
    if (const std::string e = begin(); !e.empty()) {
      std::cerr << "error: " << e << "\n";
      return 1;
    }
  }
  reload_asked_ = false;
  while (!quit_ && !stop_ && !quit_requested() && (limit < 0 || stats_.frames < limit)) {
    // SIGHUP, or a saved edit (between frames: a non-blocking read): the edited show is
    // prepared on a thread of its own while this one plays on (live_reload.cpp).
    // (a saved edit noticed and its preparation started: the reload's allocations, counted apart
    // from the frames' as the swap's are, LiveShow::reloaded)
    const uint64_t before_reload = allocations();
    if (take_reload_request()) start_reload("SIGHUP");
    if (watch_ && stats_.frames % 8 == 0)
      if (const std::string cause = watch_->poll(monotonic_ns()); !cause.empty()) start_reload(cause);
    const bool ready = reload_ready();  // (which may start the newest edit, or give one up)
    alloc_base_ += allocations() - before_reload;
    if (ready) {
      swap_allocs_ = allocations();  // from here to reloaded(): the swap's, counted apart
      reload_asked_ = true;
      break;
    }
    int64_t t = pacer_.time_of(stats_.frames);
    if (playback_) {
      int it = governor_.iterations();
      if (!playback_->next_frame(replay_wires_, t, it, [&](uint16_t src, std::span<const uint8_t> d) { replay_device(src, d); })) {
        if (!playback_->damage().empty()) std::cerr << "error: " << playback_->damage() << std::endl;
        break;
      }
      governor_.force(it);
    }
    if (canvas_->is_window()) {
      // What the window system allocates to hand over its events (Xlib reads a title change's
      // PropertyNotify with replies it allocates) is counted apart, as presenting's is.
      const uint64_t before_events = allocations();
      const bool go = handle_window_events();
      const uint64_t n = allocations() - before_events;
      if (stats_.frames >= opt_.warmup) present_allocs_ += n;
      alloc_base_ += n;
      if (!go) break;
    }
    await_simulation(t);
    const long k = stats_.frames;
    frame(t);
    if (mapping_.take_takeover_news()) takeover_pending_ = true;
    if (takeover_pending_) takeover_pending_ = tell_takeover_waits(t);  // (between frames)
    uint16_t news_of = 0;
    for (const char* news = nullptr; leds_.take_news(news_of, news);)  // a controller's setup (loop/korg_setup.h)
      if (!opt_.quiet) std::fprintf(stderr, "note: device '%s': %s\n", show_.devices[news_of].name.c_str(), news);
    if (late_.timed()) {  // the frame against its deadline, on the show clock (loop/late_input.h)
      const int64_t e = pacer_.epoch();
      auto show_ns = [&](double us) { return int64_t(us * 1e3) - e; };
      late_.frame(pacer_.deadline(k) - e, show_ns(marks_[0]), show_ns(marks_[1]), show_ns(marks_[2]), newest_ns_,
                  stats_.frames > opt_.warmup);
    }
    if (learn) {
      if (!learn_from_events()) return 1;
      if (learned_) break;
    }
    if (!playback_) pacer_.wait_for(stats_.frames, late_.lead_us());  // frame pacing, outside the frame
  }
  if (reload_asked_) return 0;  // the outputs, the recording and the clock go on in the reloaded show
  if (simulation_) simulation_->deliver_sent();  // --simulate: the simulators show the lights they were sent
  bool outputs_ok = outputs_->finish(opt_.quiet);  // (a file that could not be written: exit 1, after the show)
  if (recorder_ && !recorder_->flush()) {
    std::cerr << "error: " << recorder_->error() << ": the take is cut there\n";
    outputs_ok = false;
  }
  if (playback_ && !playback_->damage().empty()) outputs_ok = false;
  if (learn && !learned_) {
    std::cerr << "error: no control moved; nothing learned for " << opt_.learn << "\n";
    return 1;
  }
  if (!opt_.quiet) {
    std::cout << stats_.frames << " frames, frame p50 " << std::lround(stats_.frame.quantile(0.5)) << " us, p99 "
              << std::lround(stats_.frame.quantile(0.99)) << " us, overruns " << stats_.overruns << ", run_hash " << std::hex
              << run_hash() << std::dec << std::endl;
  }
  if (!opt_.stats_path.empty()) {
    if (const std::string e = write_file(opt_.stats_path, stats_json()); !e.empty()) {
      std::cerr << "error: " << e << " (the stats)\n";
      return 1;
    }
  }
  return outputs_ok ? 0 : 1;
}

}  // namespace mar
