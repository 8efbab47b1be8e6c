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

bool display_present() {
  const char* x = std::getenv("DISPLAY");
  const char* wl = std::getenv("WAYLAND_DISPLAY");
  return (x && *x) || (wl && *wl);
}

}  // namespace

void set_allocation_counter(AllocationCounter f) { g_counter = f; }
uint64_t LiveShow::allocation_count() { return allocations(); }

LiveShow::~LiveShow() {
  if (simulation_) simulation_->stop();
  devices_.reset();
}


std::string LiveShow::validate(const std::string& path) {
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  auto s = prepare(path, o);  // everything load() reads and checks, with no device or window
  return s.ok() ? std::string() : s.error;
}


Result<std::unique_ptr<LiveShow>> LiveShow::load(const std::string& path, const RunOptions& o, LiveShow* previous) {
  auto s = prepare(path, o);
  if (!s.ok()) return s;
  return take_over(std::move(*s.value), previous);
}

Result<std::unique_ptr<LiveShow>> LiveShow::prepare(const std::string& path, const RunOptions& o) {
  using R = Result<std::unique_ptr<LiveShow>>;
  std::unique_ptr<LiveShow> s(new LiveShow());
  s->opt_ = o;
  // The show file is parsed once; its [show] table names the rig (or its [[character]] tables
  // the cast's), and the rest is resolved against the loaded puppets: their handles and the
  // settings a binding may drive.
  std::vector<std::unique_ptr<Puppet>> puppets;
  auto show = load_show(path, [&](const ShowConfig& header) -> Result<ShowRig> {
    using RR = Result<ShowRig>;
    auto load_one = [&](const std::string& character, const std::string& rig) -> std::string {
      // (on the canvas begin() makes, curves are flattened to within 0.1 px)
      auto puppet = load_puppet(character, rig, "", true, header.images_anywhere, canvas_size(o, header));
      if (!puppet.ok()) return puppet.error;
      if (!s->opt_.quiet)
        for (const std::string& w : (*puppet.value)->character.warnings) std::cerr << "warning: " << w << "\n";
      puppets.push_back(std::move(*puppet.value));
      return {};
    };
    if (header.cast.empty()) {
      if (std::string e = load_one(header.character, header.rig); !e.empty()) return RR::failure(e);
      return RR::success(show_rig(*puppets.front(), header));
    }
    std::vector<ShowRig> rigs;
    std::vector<std::string> names;
    for (const ShowCharacter& c : header.cast) {
      if (std::string e = load_one(c.character, c.rig); !e.empty())
        return RR::failure(header.path + ":" + std::to_string(c.line) + ": character '" + c.name + "': " + e);
      rigs.push_back(show_rig(*puppets.back(), header));
      names.push_back(c.name);
    }
    return RR::success(cast_rig(names, std::move(rigs)));
  });
  if (!show.ok()) return R::failure(show.error);
  s->show_ = std::move(*show.value);
  ShowConfig& sh = s->show_;
  s->pacer_ = Pacer(1.0 / (o.rate > 0 ? o.rate : sh.rate_hz), false);
  s->governor_ = Governor(sh.iterations, sh.min_iterations);
  if (o.kiosk) sh.kiosk.enabled = true;
  s->hud_ = sh.hud && !sh.kiosk.enabled;
  if (auto c = parse_background_color(sh.background)) s->background_ = *c;

  // One mapping for the whole cast: every actor's handles, settings, swap sets and triggers are a
  // range of its own (loop/actor.h), in ShowRig order.
  Mapping& m = s->mapping_;
  std::vector<std::string> names;
  std::vector<Vec2> rest;
  for (size_t c = 0; c < puppets.size(); ++c) {
    for (const auto& h : puppets[c]->rig.handles) names.push_back(sh.cast.empty() ? h.name : sh.cast[c].name + "." + h.name);
    const std::vector<Vec2> r = puppets[c]->rest_targets();
    rest.insert(rest.end(), r.begin(), r.end());
  }
  m.set_handles(names, rest);
  // Settings: the iteration count (the governor's ceiling), then each actor's own.
  s->setting_iterations_ = m.add_setting({double(sh.iterations), double(sh.min_iterations), 200, true});
  size_t h0 = 0, sw0 = 0, tr0 = 0;
  for (size_t c = 0; c < puppets.size(); ++c) {
    // Swap sets and triggers: what shows (the rig's defaults until a control changes them).
    for (const RigSwap& sw : puppets[c]->rig.swaps) {
      s->swap_counts_.push_back(int(sw.members.size()));
      s->swap_members_.push_back(sw.default_member);
    }
    const size_t nh = puppets[c]->rig.handles.size(), nsw = puppets[c]->rig.swaps.size(), ntr = puppets[c]->rig.triggers.size();
    auto a = std::make_unique<Actor>();
    if (!sh.cast.empty()) {
      const ShowCharacter& sc = sh.cast[c];
      a->set_name(sc.name);
      a->shown = sc.shown;
      a->z = sc.z;
      a->fade = sc.entrance == "fade";
      a->entrance_s = sc.entrance == "cut" ? 0.0 : sc.entrance_seconds;
    }
    if (std::string e = a->prepare(std::move(puppets[c]), sh, m, h0, sw0, tr0, int(c)); !e.empty()) return R::failure(e);
    h0 += nh;
    sw0 += nsw;
    tr0 += ntr;
    s->actors_.push_back(std::move(a));
  }
  for (const auto& a : s->actors_) s->z_order_.push_back(a.get());
  s->quality_.assign(s->actors_.size(), 0.0);
  if (!sh.cast.empty()) {
    size_t nh = 0, nk = 0;
    for (const auto& a : s->actors_) {
      nh += a->puppet().rig.handles.size();
      nk += a->puppet().rig.keys.size();
    }
    s->cast_handles_.assign(nh, Vec2::Zero());
    s->cast_keys_.assign(nk, 0.0);
  }
  if (s->actors_.size() > 1) {
    // The cast's solves in parallel: one thread a character, up to the cores, from 4 characters
    // on (bench_cast on 2 cores: 2 characters' solve p50 116 us alone, 154 us on the pool —
    // waking a helper costs more than it saves; 4: 210 / 206; 8: 416 / 315; 16: 815 / 509).
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    const int n = sh.threads > 0 ? sh.threads : s->actors_.size() >= 4 ? std::min(cores, int(s->actors_.size())) : 1;
    if (n > 1) s->pool_ = std::make_unique<WorkerPool>(n);
  }
  std::stable_sort(s->z_order_.begin(), s->z_order_.end(), [](const Actor* x, const Actor* y) { return x->z < y->z; });
  // A cast's NAME.on-stage triggers, after the rigs' (each on as its character is shown at the start).
  s->stage_trigger0_ = int(tr0);
  s->triggers_on_.assign(tr0 + sh.cast.size(), 0);
  m.set_swaps(s->swap_counts_, s->swap_members_, tr0 + sh.cast.size());
  for (size_t c = 0; c < sh.cast.size(); ++c) {
    s->triggers_on_[tr0 + c] = sh.cast[c].shown;
    m.set_trigger(tr0 + c, sh.cast[c].shown);
  }
  {
    const auto [cw, chh] = canvas_size(o, sh);
    const int ss = std::clamp(o.supersample, 1, 8);
    s->place_cast(cw * ss, chh * ss, ss);
    // Scenery and props (loop/stage_drawings.h), loaded here: off a running show's frame thread.
    if (std::string e = s->stage_.load(sh, s->actors_, {cw, chh}, ss, s->background_, o.quiet); !e.empty()) return R::failure(e);
  }
  for (auto& g : sh.groups) m.add_group(g);
  for (auto& po : sh.poses) m.add_pose(po);
  auto actor_of = [&](const Binding& b) -> const Actor& {  // (a pointer's character: its handle's, or its grab's)
    if (b.target == TargetKind::Grab) return *s->actors_[size_t(b.index)];
    for (const auto& a : s->actors_)
      if (b.target == TargetKind::HandlePoint && size_t(b.index) >= a->ranges().handle0 &&
          size_t(b.index) < a->ranges().handle0 + a->ranges().handles)
        return *a;
    return *s->actors_.front();
  };
  for (Binding b : sh.bindings) {
    if (b.control.kind == ControlSpec::Pointer && b.tf.area[0] == 0 && b.tf.area[2] == 1) {
      // Default pointer area: the tablet covers the character's bounding box.
      const Bounds bb = actor_of(b).rest_bounds;
      b.tf.area[0] = bb.lo.x();
      b.tf.area[1] = bb.lo.y();
      b.tf.area[2] = bb.hi.x();
      b.tf.area[3] = bb.hi.y();
    }
    m.add_binding(b);
  }
  s->idle_.prepare(sh, m);  // after the bindings: each behaviour pauses while one on its target moves
  s->leds_.prepare(sh, m);  // the controllers' lights the bindings drive

  for (size_t i = 0; i < sh.devices.size(); ++i) {
    ShowDevice& d = sh.devices[i];
    const bool hardware = d.type != "sim";
    s->has_hardware_ = s->has_hardware_ || hardware;
    if (d.sim.empty() || (hardware && !o.simulate)) continue;  // (a reload that keeps them drops these)
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
    (*dev.value)->set_voice(d.voice);
    if (auto ok = (*dev.value)->load_script(d.script); !ok.ok())
      return R::failure(sh.path + ":" + std::to_string(d.line) + ": device '" + d.name + "' script " + ok.error);
    s->sims_.resize(sh.devices.size());
    s->sims_[i] = std::move(*dev.value);
  }
  if (sh.attract.after > 0) {  // after the bindings: the attract starts from the mapping as loaded
    const AttractConfig& ac = sh.attract;
    const ShowDevice* d = ac.device >= 0 ? &sh.devices[size_t(ac.device)] : nullptr;
    // The descriptor as the device's simulator uses it: a corpus file that is not here leaves the
    // built-in one (as above, and as the show file's check of the script did).
    const bool absent = d && d->descriptor_in_corpus && !std::filesystem::exists(d->descriptor);
    const std::string descriptor = d && !absent ? d->descriptor : "";
    auto a = Attract::make(ac, m, d ? d->sim : "", descriptor, uint16_t(std::max(0, ac.device)),
                           d ? int64_t(d->debounce_ms * 1e6) : 0);
    if (!a.ok()) return R::failure(sh.path + ":" + std::to_string(ac.line) + ": [attract]: " + a.error);
    s->attract_ = std::move(*a.value);
  }
  s->wires_.resize(4096);
  s->events_.resize(4096);
  s->targets_ = rest;
  s->replay_wires_.reserve(1 << 16);
  s->replay_decoders_.resize(sh.devices.size());
  s->replay_retired_.resize(sh.devices.size());
  s->device_states_.assign(sh.devices.size(), DeviceState::Connected);
  s->last_events_.assign(sh.devices.size(), Event{});
  return R::success(std::move(s));
}

Result<std::unique_ptr<LiveShow>> LiveShow::take_over(std::unique_ptr<LiveShow> s, LiveShow* previous) {
  using R = Result<std::unique_ptr<LiveShow>>;
  if (previous) s->restarted_ = s->keeps(*previous);  // a reload: what it cannot keep (empty: all)
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
  if (!opt_.headless && display_present()) {
    WindowOptions wo;
    wo.title = "marionette - " + std::filesystem::path(sh.path).stem().string();
    wo.width = sh.width;
    wo.height = sh.height;
    wo.fullscreen = sh.fullscreen || sh.kiosk.enabled;
    wo.screen = sh.kiosk.enabled ? sh.kiosk.display : sh.screen;
    wo.screen_name = sh.kiosk.enabled ? std::string() : sh.screen_name;
    wo.transparent = background_.a < 1;
    wo.vsync = sh.vsync;
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
    } else if (!opt_.quiet) {
      std::cerr << "warning: no window (" << w.error << "); running headless\n";
    }
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

void LiveShow::place_cast(int w, int h, int ss) {
  // A show's single rig fills the canvas (less a margin). A cast stands side by side: the
  // characters with no position each in its share of the canvas's width, as it would fill it
  // alone; then each is scaled and turned about its box's centre, which goes to its position.
  size_t free = 0;
  for (const ShowCharacter& sc : show_.cast) free += sc.has_position ? 0 : 1;
  const double share = double(w) / double(std::max<size_t>(1, free));
  for (size_t c = 0, next = 0; c < actors_.size(); ++c) {
    Actor& a = *actors_[c];
    const Character& ch = a.puppet().character;
    if (show_.cast.empty()) {
      a.view = fit_view(ch.width, ch.height, w, h, kShowMargin * ss);
      continue;
    }
    const ShowCharacter& sc = show_.cast[c];
    const double k = fit_view(ch.width, ch.height, int(share), h, kShowMargin * ss).a * sc.scale;
    const Vec2 at = sc.has_position ? Vec2(sc.position * ss) : Vec2(share * (double(next++) + 0.5), 0.5 * h);
    a.view = Affine2::translate(at.x(), at.y()) * Affine2::rotate(sc.rotation) * Affine2::scale(k, k) *
             Affine2::translate(-0.5 * ch.width, -0.5 * ch.height);
    // A slide comes from (and goes to) just beyond the canvas's edge on its side.
    const std::string& e = sc.entrance;
    a.offstage = e == "slide-left" ? Vec2(-at.x() - 0.5 * k * ch.width, 0) : e == "slide-right" ? Vec2(w - at.x() + 0.5 * k * ch.width, 0)
               : e == "slide-up" ? Vec2(0, -at.y() - 0.5 * k * ch.height) : e == "slide-down" ? Vec2(0, h - at.y() + 0.5 * k * ch.height)
                                 : Vec2(0, 0);
  }
}

void LiveShow::osc_names(OutputsSpec& out) const {
  if (show_.cast.empty()) {
    out.set_osc(show_, lead().puppet().rig);
    return;
  }
  std::vector<const Rig*> rigs;
  std::vector<std::string> names;
  for (const auto& a : actors_) {
    rigs.push_back(&a->puppet().rig);
    names.push_back(a->name());
  }
  out.set_osc(show_, rigs, names);
}

void LiveShow::cast_state() {
  // A cast's handles and key weights for the outputs, every character's in the cast's order (a
  // character with no key stage: its keys at 0).
  size_t h = 0, k = 0;
  for (const auto& a : actors_) {
    const Puppet& p = a->puppet();
    for (size_t i = 0; i < p.rig.handles.size(); ++i) cast_handles_[h++] = p.solver->handle_point(i);
    const auto w = a->key_weights();
    for (size_t i = 0; i < p.rig.keys.size(); ++i) cast_keys_[k++] = i < w.size() ? w[i] : 0.0;
  }
}

void LiveShow::reserve_layers() {
  // A character that fades in late draws a layer no earlier frame had: its buffers are made now.
  size_t depth = 0, count = 0;
  for (const auto& a : actors_) {
    depth = std::max(depth, a->layer_depth());
    count += a->layer_count();
  }
  if (depth > 0) canvas_->reserve_layers(depth);
  list_.layers.reserve(count);
}

std::vector<std::string> LiveShow::watched_files() const {
  std::vector<std::string> files{show_.path};
  for (const auto& a : actors_) {
    files.push_back(a->puppet().rig.path);
    files.push_back(a->puppet().character.source);
  }
  return files;
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
  if (!leds_.empty() && !playback_) leds_.frame(t_ns, mapping_, swap_members_, triggers_on_, device_states_, lights_);
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
    idle_.apply_targets(targets_, show_.groups);
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
  quality_pct_ = *std::max_element(quality_.begin(), quality_.end());
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
      // A cast: the box round them all, kept off whole.
      Vec2 lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
      for (const auto& a : actors_)
        for (const Vec2& c : {a->rest_bounds.lo, a->rest_bounds.hi, Vec2(a->rest_bounds.lo.x(), a->rest_bounds.hi.y()),
                              Vec2(a->rest_bounds.hi.x(), a->rest_bounds.lo.y())}) {
          const Vec2 v = a->view.apply(c);
          lo = lo.cwiseMin(v);
          hi = hi.cwiseMax(v);
        }
      const HudAvoid avoid{shown.x + int(lo.x() * sx), shown.y + int(lo.y() * sy), int((hi.x() - lo.x()) * sx), int((hi.y() - lo.y()) * sy),
                           actors_.size() == 1 ? Actor::kCoverCells : 0, actors_.size() == 1 ? lead().rest_cover.data() : nullptr};
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
  if (!show_.cast.empty()) cast_state();
  compute_us += outputs_->frame(uint64_t(stats_.frames), t_ns, lead().puppet(), *canvas_,
                               {show_.cast.empty() ? lead().key_weights() : std::span<const double>(cast_keys_),
                                std::span<const Vec2>(cast_handles_), swap_members_, triggers_on_, device_states_, compute_us * 1e-3, newest_ns < 0 ? -1 : double(t_ns - newest_ns) * 1e-6 + compute_us * 1e-3});
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
  if (std::string e = outputs_->open(out, lead().puppet().character); !e.empty()) return e;
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
