#include "app/loop/stage_drawings.h"

#include "character/load.h"
#include "geom/polygon.h"

#include <algorithm>
#include <cmath>
#include <iostream>

namespace mar {

std::string StageDrawings::load(const ShowConfig& sh, const std::vector<std::unique_ptr<Actor>>& cast, std::array<int, 2> canvas,
                                int ss, const Rgba& background, bool quiet) {
  const double cw = canvas[0], chh = canvas[1];
  for (const ShowScenery& sc : sh.scenery) {
    LoadOptions lo;
    lo.pixels_per_unit = [cw, chh, &sc](double w, double h) {
      w = std::max(w, 1e-9);
      h = std::max(h, 1e-9);
      return sc.fit == ShowScenery::Placed ? sc.width / w : sc.fit == ShowScenery::Cover ? std::max(cw / w, chh / h) : std::min(cw / w, chh / h);
    };
    auto c = load_character(sc.file, lo);
    if (!c.ok()) return sh.path + ":" + std::to_string(sc.line) + ": scenery: " + c.error;
    if (!quiet)
      for (const std::string& w : c.value->warnings) std::cerr << "warning: " << w << "\n";
    Scenery v{std::move(*c.value), {}, Affine2::identity(), sc};
    v.mesh = prepare_mesh(v.ch);
    scenery_.push_back(std::move(v));
  }
  if (std::any_of(scenery_.begin(), scenery_.end(), [](const Scenery& v) { return !v.spec.front; })) {
    // Drawn once: config/shows/stage.toml's full-canvas gradient sky took 15.1 ms a frame drawn
    // each frame, 0.94 ms copied (docs/live-shows.md#scenery).
    place(cw * ss, chh * ss, ss);
    auto c = Canvas::offscreen(canvas[0] * ss, canvas[1] * ss);
    if (c.ok()) {
      Canvas& off = **c.value;
      DrawList list;
      for (const Scenery& v : scenery_)
        if (!v.spec.front) build_draw_list(v.ch, v.mesh, {}, v.view, 0.3, list);
      off.clear(background);
      if (off.draw(list).empty()) backdrop_ = off.read_premultiplied();
    }
  }
  for (const ShowProp& pr : sh.props) {
    const std::string where = sh.path + ":" + std::to_string(pr.line) + ": prop: ";
    // In a cast the part is NAME.PART: the holding character's name, then its shape id.
    int who = 0;
    std::string id = pr.part;
    if (!sh.cast.empty()) {
      who = -1;
      const size_t dot = pr.part.find('.');
      for (size_t c = 0; c < cast.size() && dot != std::string::npos; ++c)
        if (cast[c]->name() == pr.part.substr(0, dot)) who = int(c);
      if (who < 0) return where + "'" + pr.part + "': in a cast the part is NAME.PART, the character's name, then its part";
      id = pr.part.substr(dot + 1);
    }
    const Puppet& p = cast[size_t(who)]->puppet();
    int part = -1;
    for (size_t k = 0; k < p.character.shapes.size(); ++k)
      if (p.character.shapes[k].id == id) part = int(k);
    if (part < 0) return where + "the character has no part '" + id + "' (a shape id of " + p.character.source + ")";
    // (a prop is flattened at the size it is drawn: its width in character units, at the view's scale)
    const Affine2& v0 = cast[size_t(who)]->view;
    const double view_k = std::sqrt(std::abs(v0.a * v0.d - v0.b * v0.c)) / ss;
    LoadOptions lo;
    lo.pixels_per_unit = [&pr, view_k](double w, double) { return (pr.width > 0 ? pr.width / std::max(w, 1e-9) : 1.0) * view_k; };
    auto c = load_character(pr.file, lo);
    if (!c.ok()) return where + c.error;
    Prop v;
    v.ch = std::move(*c.value);
    v.mesh = prepare_mesh(v.ch);
    v.part = part;
    v.who = who;
    v.front = pr.front;
    const Bounds hb = p.character.shapes[size_t(part)].bounds();
    const Vec2 at = pr.has_at ? pr.at : Vec2(0.5 * (hb.lo + hb.hi));
    const double k = pr.width > 0 ? pr.width / std::max(1e-9, v.ch.width) : 1.0;
    v.place = Affine2::translate(at.x(), at.y()) * Affine2::rotate(pr.rotation) * Affine2::scale(k, k) *
              Affine2::translate(-0.5 * v.ch.width, -0.5 * v.ch.height);
    props_.push_back(std::move(v));
  }
  return {};
}

void StageDrawings::place(double W, double H, double ss) {
  // Cover: fills the canvas, centred, what overflows cut; contain: inside it, centred; placed:
  // its top-left corner at `at` and `width` wide (canvas pixels at the show's size).
  for (Scenery& sc : scenery_) {
    const double w = std::max(1e-9, sc.ch.width), h = std::max(1e-9, sc.ch.height);
    double k = 0, x = 0, y = 0;
    if (sc.spec.fit == ShowScenery::Placed) {
      k = sc.spec.width * ss / w;
      x = sc.spec.at.x() * ss;
      y = sc.spec.at.y() * ss;
    } else {
      k = sc.spec.fit == ShowScenery::Cover ? std::max(W / w, H / h) : std::min(W / w, H / h);
      x = 0.5 * (W - k * w);
      y = 0.5 * (H - k * h);
    }
    sc.view = Affine2{k, 0, 0, k, x, y};
  }
}

void StageDrawings::append_props(const Actor& a, bool front, DrawList& list) const {
  // A prop moves as its part: the part's best rigid motion from rest to now.
  const Puppet& p = a.puppet();
  const Affine2 view = a.drawn_view();
  for (const Prop& pr : props_) {
    if (pr.front != front || pr.who != a.ranges().who) continue;
    const RigidMotion m = rigid_fit(p.character.shapes[size_t(pr.part)].points, p.shapes[size_t(pr.part)]);
    const Affine2 move = Affine2::translate(m.to_c.x(), m.to_c.y()) * Affine2{m.c, m.s, -m.s, m.c, 0, 0} *
                         Affine2::translate(-m.from_c.x(), -m.from_c.y());
    build_draw_list(pr.ch, pr.mesh, {}, view * move * pr.place, 0.3, list, {}, a.opacity());
  }
}

void StageDrawings::append_scenery(bool front, DrawList& list) const {
  if (!front && copied_) return;
  for (const Scenery& sc : scenery_)
    if (sc.spec.front == front) build_draw_list(sc.ch, sc.mesh, {}, sc.view, 0.3, list);
}

}  // namespace mar
