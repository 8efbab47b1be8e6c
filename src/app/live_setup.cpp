// Preparing a show (live.h): reading and checking it, its rig or its cast, the names they offer,
// the canvas it draws on, the cast's places on it; off a running show's frame thread on a reload.
#include "app/live.h"

#include "app/simulate.h"
#include "character/color.h"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <thread>

namespace mar {

// What a show's names resolve against once its rig is loaded (load_show's RigLoader): the
// puppet's handles, the loop's and the solver's settings, the key poses, swap sets and triggers.
ShowRig show_rig(const Puppet& p, const ShowConfig& header) {
  ShowRig rig;
  for (const auto& h : p.rig.handles) rig.handles.push_back(h.name);
  rig.rest = p.rest_targets();
  rig.diag = p.diagonal;
  rig.settings.push_back({"iterations", std::pair<double, double>(header.min_iterations, header.iterations)});
  for (const SolverParameter& sp : p.loaded_parameters) rig.settings.push_back({sp.name, std::nullopt});
  // Key poses: morph.FROM.TO for every ordered pair of rest and the keys, blend.KEY per key.
  if (p.feature_frame() && !p.rig.keys.empty()) {
    std::vector<std::string> names{"rest"};
    for (const RigKey& k : p.rig.keys) names.push_back(k.name);
    for (size_t a = 0; a < names.size(); ++a)
      for (size_t b = 0; b < names.size(); ++b)
        if (a != b) rig.settings.push_back({"morph." + names[a] + "." + names[b], std::pair<double, double>(0, 1)});
    for (const RigKey& k : p.rig.keys) rig.settings.push_back({"blend." + k.name, std::pair<double, double>(0, 1)});
    for (const RigKey& k : p.rig.keys) rig.keys.push_back(k.name);
  }
  // Secondary motion: physics.NAME.strength|mix, physics.wind|gravity|reset.
  for (const PhysicsStage::SettingInfo& si : PhysicsStage::setting_names(p))
    rig.settings.push_back({si.name, std::pair<double, double>(si.lo, si.hi)});
  for (const RigSwap& sw : p.rig.swaps) rig.swaps.push_back({sw.name, sw.members});
  for (const RigTrigger& tr : p.rig.triggers) rig.triggers.push_back(tr.name);
  return rig;
}


// The canvas: [output]'s size, else the window's (a run's --size before either).
std::array<int, 2> canvas_size(const RunOptions& o, const ShowConfig& sh) {
  return {o.width > 0 ? o.width : sh.out_width > 0 ? sh.out_width : sh.width,
          o.height > 0 ? o.height : sh.out_height > 0 ? sh.out_height : sh.height};
}


Result<std::unique_ptr<LiveShow>> LiveShow::prepare(const std::string& path, const RunOptions& o, std::vector<KeptPuppet> keep) {
  using R = Result<std::unique_ptr<LiveShow>>;
  std::unique_ptr<LiveShow> s(new LiveShow());
  s->opt_ = o;
  // The show file is parsed once; its [show] table names the rig (or its [[character]] tables
  // the cast's), and the rest is resolved against the loaded puppets: their handles and the
  // settings a binding may drive.
  std::vector<std::shared_ptr<Puppet>> puppets;
  auto show = load_show(path, [&](const ShowConfig& header) -> Result<ShowRig> {
    using RR = Result<ShowRig>;
    auto load_one = [&](const std::string& name, const std::string& character, const std::string& rig) -> std::string {
      const std::array<int, 2> canvas = canvas_size(o, header);
      const bool brushed = std::find(header.brushed.begin(), header.brushed.end(), name) != header.brushed.end();
      const double spacing = brushed ? kSculptSpacing : 0.0;  // (a brush's outline: a finer frame)
      // A reload: a character loaded the same way from the same bytes is the running show's
      // puppet (its key poses solved, if it has keys: solving them would pose it here).
      for (KeptPuppet& k : keep) {
        if (!k.puppet || k.name != name || k.character != character || k.rig != rig || k.canvas != canvas ||
            k.images_anywhere != header.images_anywhere)
          continue;
        const Puppet& p = *k.puppet;
        if (p.stamp.empty() || (!p.rig.keys.empty() && !p.solved_keys) || p.rig.max_spacing != std::max(spacing, sculpt_spacing(p.rig)) ||
            puppet_stamp(p) != p.stamp)
          break;
        puppets.push_back(std::move(k.puppet));
        s->kept_.push_back(name);
        return {};
      }
      // (on the canvas begin() makes, curves are flattened to within 0.1 px)
      Result<Rig> loaded_rig = load_rig(rig);
      if (!loaded_rig.ok()) return loaded_rig.error;
      loaded_rig.value->max_spacing = std::max(spacing, sculpt_spacing(*loaded_rig.value));  // (or its sculpted keys')
      auto puppet = load_puppet(character, std::move(*loaded_rig.value), "", true, header.images_anywhere, canvas);
      if (!puppet.ok()) return puppet.error;
      // (room for a brush's targets in every feature frame: a reload may add a [[brush]] and keep it)
      if (FeatureFrameMethod* ff = (*puppet.value)->feature_frame()) ff->core().reserve_soft(kSoftTargets);
      if (!s->opt_.quiet)
        for (const std::string& w : (*puppet.value)->character.warnings) std::cerr << "warning: " << w << "\n";
      puppets.push_back(std::move(*puppet.value));
      return {};
    };
    if (header.cast.empty()) {
      if (std::string e = load_one("", header.character, header.rig); !e.empty()) return RR::failure(e);
      return RR::success(show_rig(*puppets.front(), header));
    }
    std::vector<ShowRig> rigs;
    std::vector<std::string> names;
    for (const ShowCharacter& c : header.cast) {
      if (std::string e = load_one(c.name, c.character, c.rig); !e.empty())
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
  if (s->actors_.size() > 1 && (!sh.brushes.empty() || !sh.curves.empty()))  // (one pen, tools on several characters)
    m.set_pen_hit([show = s.get()](int who, const Vec2& p) { return show->pen_over(who, p); });
  s->quality_.assign(s->actors_.size(), 0.0);
  if (!sh.cast.empty()) {
    size_t nh = 0, nk = 0;
    for (const auto& a : s->actors_) {
      nh += a->puppet().rig.handles.size();
      nk += a->puppet().rig.keys.size();
    }
    s->cast_handles_.assign(nh, Vec2::Zero());
    s->cast_keys_.assign(nk, 0.0);
    for (const auto& a : s->actors_)
      for (const SubShape& p : a->puppet().character.shapes) s->cast_shapes_.push_back(p.points);  // (the rest: a kept puppet is posed meanwhile)
    s->cast_shown_.assign(s->cast_shapes_.size(), 1);
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
    if (b.target == TargetKind::Grab || b.target == TargetKind::Brush || b.target == TargetKind::Curve) return *s->actors_[size_t(b.index)];
    for (const auto& a : s->actors_)
      if (b.target == TargetKind::HandlePoint && size_t(b.index) >= a->ranges().handle0 &&
          size_t(b.index) < a->ranges().handle0 + a->ranges().handles)
        return *a;
    return *s->actors_.front();
  };
  const auto [canvas_w, canvas_h] = canvas_size(o, sh);
  const double ss_px = std::clamp(o.supersample, 1, 8);
  for (Binding b : sh.bindings) {
    const bool default_area = b.tf.area[0] == 0 && b.tf.area[1] == 0 && b.tf.area[2] == 1 && b.tf.area[3] == 1;
    if (b.control.kind == ControlSpec::Pointer && (b.tf.area_canvas || (!sh.cast.empty() && default_area))) {
      // Over the canvas: the point under the pen (or the mouse over the window) is the
      // character's point under it, wherever it stands and however it is scaled and turned.
      const Affine2 to = actor_of(b).view.inverse() * Affine2::scale(canvas_w * ss_px, canvas_h * ss_px);
      b.tf.area_canvas = true;
      const double c[6] = {to.a, to.b, to.c, to.d, to.e, to.f};
      std::copy(c, c + 6, b.tf.canvas_map);
    } else if (b.control.kind == ControlSpec::Pointer && default_area) {
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
      a.px_per_unit = a.view.a / ss;
      continue;
    }
    const ShowCharacter& sc = show_.cast[c];
    const double k = fit_view(ch.width, ch.height, int(share), h, kShowMargin * ss).a * sc.scale;
    const Vec2 at = sc.has_position ? Vec2(sc.position * ss) : Vec2(share * (double(next++) + 0.5), 0.5 * h);
    a.view = Affine2::translate(at.x(), at.y()) * Affine2::rotate(sc.rotation) * Affine2::scale(k, k) *
             Affine2::translate(-0.5 * ch.width, -0.5 * ch.height);
    a.px_per_unit = k / ss;
    // A slide comes from (and goes to) just beyond the canvas's edge on its side.
    const std::string& e = sc.entrance;
    a.offstage = e == "slide-left" ? Vec2(-at.x() - 0.5 * k * ch.width, 0) : e == "slide-right" ? Vec2(w - at.x() + 0.5 * k * ch.width, 0)
               : e == "slide-up" ? Vec2(0, -at.y() - 0.5 * k * ch.height) : e == "slide-down" ? Vec2(0, h - at.y() + 0.5 * k * ch.height)
                                 : Vec2(0, 0);
  }
  if (actors_.size() < 2) return;
  // Where the cast's drawings cover the canvas at rest (the HUD keeps off them): the box round
  // them all, in cells, each covered when a filled shape of a character holds its centre.
  Vec2 lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
  for (const auto& a : actors_) {
    const Bounds& b = a->rest_bounds;
    for (const Vec2& c : {b.lo, b.hi, Vec2(b.lo.x(), b.hi.y()), Vec2(b.hi.x(), b.lo.y())}) {
      lo = lo.cwiseMin(a->view.apply(c));
      hi = hi.cwiseMax(a->view.apply(c));
    }
  }
  cast_box_ = Bounds{lo.cwiseMax(Vec2(0, 0)), hi.cwiseMin(Vec2(w, h))};
  cast_cover_.assign(size_t(Actor::kCoverCells) * Actor::kCoverCells, 0);
  for (const auto& a : actors_) {
    const auto cells = cover_cells(a->puppet().character, cast_box_, Actor::kCoverCells, a->view.inverse());
    for (size_t i = 0; i < cells.size(); ++i) cast_cover_[i] |= cells[i];
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
  // character with no key stage: its keys at 0); and its shapes for a pose dump.
  size_t h = 0, k = 0, s = 0;
  for (const auto& a : actors_) {
    const Puppet& p = a->puppet();
    for (size_t i = 0; i < p.rig.handles.size(); ++i) cast_handles_[h++] = p.solver->handle_point(i);
    const auto w = a->key_weights();
    for (size_t i = 0; i < p.rig.keys.size(); ++i) cast_keys_[k++] = i < w.size() ? w[i] : 0.0;
    if (opt_.dump_poses.empty()) continue;
    for (size_t i = 0; i < p.shapes.size(); ++i, ++s) {
      std::copy(p.shapes[i].begin(), p.shapes[i].end(), cast_shapes_[s].begin());
      cast_shown_[s] = i < p.shown.size() ? p.shown[i] : 1;
    }
  }
}

const Character& LiveShow::outputs_drawing() {
  // A cast's pose dump lists every character's shapes, each id with its character's name.
  if (show_.cast.empty()) return lead().puppet().character;
  cast_drawing_ = Character{};
  for (const auto& a : actors_)
    for (const SubShape& sub : a->puppet().character.shapes) {
      SubShape c;
      c.id = a->name() + "." + sub.id;
      c.points = sub.points;
      cast_drawing_.shapes.push_back(std::move(c));
    }
  return cast_drawing_;
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

std::vector<KeptPuppet> LiveShow::keepable() const {
  std::vector<KeptPuppet> keep;
  for (size_t c = 0; c < actors_.size(); ++c) {
    const bool cast = !show_.cast.empty();
    keep.push_back({actors_[c]->name(), cast ? show_.cast[c].character : show_.character, cast ? show_.cast[c].rig : show_.rig,
                    canvas_size(opt_, show_), show_.images_anywhere, actors_[c]->shared_puppet()});
  }
  return keep;
}

std::vector<std::string> LiveShow::watched_files() const {
  std::vector<std::string> files{show_.path};
  for (const auto& a : actors_) {
    files.push_back(a->puppet().rig.path);
    files.push_back(a->puppet().character.source);
  }
  return files;
}

}  // namespace mar
