#include "app/rig_preview.h"

#include "render/canvas.h"
#include "render/image.h"
#include "render/overlay.h"
#include "render/tessellate.h"
#include "render/text.h"

#include <SDL.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

namespace mar {

namespace {

// A limb's colour: hues apart, dark enough for an outline on a light veil.
Rgba hue(size_t k) {
  static const Rgba kHues[] = {{0.90, 0.33, 0.05, 1}, {0.10, 0.55, 0.85, 1}, {0.85, 0.15, 0.55, 1}, {0.20, 0.65, 0.20, 1},
                               {0.60, 0.35, 0.85, 1}, {0.95, 0.70, 0.05, 1}, {0.05, 0.65, 0.60, 1}, {0.65, 0.40, 0.20, 1}};
  return kHues[k % (sizeof kHues / sizeof kHues[0])];
}

std::string point_text(const Vec2& p) {
  char b[48];
  std::snprintf(b, sizeof b, "(%.0f, %.0f)", p.x(), p.y());
  return b;
}

// A tinted copy of a part's outline (or of a stroke limb's line) for the overlay.
SubShape tint(const SubShape& s, const Rgba& c, double outline, bool fill) {
  SubShape t;
  t.id = s.id;
  t.element = "preview";
  if (fill && s.closed()) {
    t.points = s.largest_ring();
    t.contours.push_back({0, int(t.points.size()), true});
    t.fill.enabled = true;
    t.fill.color = c;
    t.fill.opacity = 0.42f;
  } else {
    t.points = s.points;
    t.contours = s.contours;
  }
  t.stroke.enabled = true;
  t.stroke.color = c;
  t.stroke.width = outline;
  t.stroke.join = LineJoin::Round;
  t.stroke.cap = LineCap::Round;
  return t;
}

}  // namespace

std::vector<std::string> rig_summary(const AutoRig& ar, const Character& ch) {
  std::vector<std::string> out;
  auto id = [&](int shape) { return shape >= 0 && size_t(shape) < ch.shapes.size() ? ch.shapes[size_t(shape)].id : std::string("?"); };
  auto parent_id = [&](const AutoRigPart& p) {
    return p.parent >= 0 && size_t(p.parent) < ar.parts.size() ? id(ar.parts[size_t(p.parent)].shape) : std::string("nothing");
  };
  size_t limbs = 0, details = 0;
  std::map<std::string, std::vector<std::string>> riders;  // part -> the details on it
  for (const AutoRigPart& p : ar.parts) {
    if (p.kind == AutoRigPart::Body) out.push_back("body: " + id(p.shape) + (p.handle.empty() ? "" : ", handle " + p.handle));
  }
  for (const AutoRigPart& p : ar.parts) {
    // (a limb of the silhouette inside the part it hangs from: said so)
    // (a part riding whole on the rigid grid, turning at its hinge: said so)
    // (on the feature frame a rider is a detail carried by its part: counted with the details)
    bool rider = false;
    for (const RigRider& d : ar.rig.riders) rider = rider || (d.part == id(p.shape) && ar.rig.solver == "rigid_grid");
    const std::string where = id(p.shape) == parent_id(p) ? " inside " + id(p.shape)
                              : rider                     ? " " + id(p.shape) + " rides whole on " + parent_id(p)
                                                          : " " + id(p.shape) + " on " + parent_id(p);
    if (p.kind == AutoRigPart::Detail && rider) {
      out.push_back("part" + where + ", off the silhouette: hinge at " + point_text(p.joint));
      continue;
    }
    // (a limb inside one shape turning whole at its joint, a [[bone]]: said so)
    bool bone = false;
    for (const RigBone& b : ar.rig.bones) bone = bone || (!p.handle.empty() && b.handle == p.handle);
    const std::string turns = bone ? " (it turns whole there)" : "";
    if (p.kind == AutoRigPart::Head)
      out.push_back("head:" + where + (p.has_joint ? ", hinge at " + point_text(p.joint) + turns : "") +
                    (p.handle.empty() ? "" : ", handle " + p.handle));
    if (p.kind == AutoRigPart::Limb) {
      ++limbs;
      out.push_back("limb" + where + (p.has_joint ? ": hinge at " + point_text(p.joint) + turns : "") +
                    (p.handle.empty() ? "" : ", handle " + p.handle));
    }
    if (p.kind == AutoRigPart::Detail) {
      ++details;
      riders[parent_id(p)].push_back(id(p.shape));
    }
  }
  if (details) {  // (the six parts most ride on, then how many more)
    std::vector<std::pair<size_t, std::string>> most;
    for (const auto& [on, ids] : riders) most.push_back({ids.size(), on});
    std::stable_sort(most.begin(), most.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    std::string line = std::to_string(details) + " detail" + (details == 1 ? "" : "s") + " ride on their parts:";
    for (size_t k = 0; k < most.size() && k < 6; ++k)
      line += " " + std::to_string(most[k].first) + (most[k].second == "nothing" ? " attached to nothing" : " on " + most[k].second) + ";";
    line.pop_back();
    if (most.size() > 6) line += "; and on " + std::to_string(most.size() - 6) + " more parts";
    out.push_back(line);
  }
  for (const RigSwap& s : ar.rig.swaps) out.push_back("swap set " + s.name + ": " + std::to_string(s.members.size()) + " shapes");
  for (const RigTrigger& t : ar.rig.triggers) out.push_back("trigger " + t.name + ": " + std::to_string(t.shapes.size()) + " shapes");
  for (const RigPhysics& c : ar.rig.physics)
    out.push_back("chain " + c.name + ": " + std::to_string(c.parts.size()) + " parts hanging from " + c.from);
  for (const AutoRigLeftOut& l : ar.left_out) out.push_back("left out: " + id(l.shape) + ", " + l.why);
  size_t hinges = 0;
  for (const AutoRigPart& p : ar.parts) hinges += p.has_joint;
  out.push_back(std::to_string(ar.rig.handles.size()) + " handles, " + std::to_string(hinges) + " hinges, " +
                std::to_string(limbs) + " limbs");
  return out;
}

std::string write_rig_preview(const std::string& path, const Character& ch, const AutoRig& ar, int long_side) {
  const double cw = std::max(ch.width, 1e-6), chh = std::max(ch.height, 1e-6);
  const double scale = double(std::clamp(long_side, 64, 4096)) / std::max(cw, chh);
  const int w = std::max(640, int(std::ceil(cw * scale))), dh = std::max(64, int(std::ceil(chh * scale)));
  const std::vector<std::string> lines = rig_summary(ar, ch);
  const int line_h = 16, legend = 10 + line_h * int(lines.size());
  const int h = dh + legend;
  auto canvas = Canvas::offscreen(w, h);
  if (!canvas.ok()) return path + ": " + canvas.error;
  Canvas& c = **canvas.value;
  c.set_antialias(true);
  c.clear(Rgba{1, 1, 1, 1});
  const Affine2 view = fit_view(ch.width, ch.height, w, dh);
  const double unit = 1.0 / std::max(1e-9, std::sqrt(std::abs(view.det())));  // one pixel in character units
  DrawList list;
  build_draw_list(ch, prepare_mesh(ch), {}, view, 0.25, list);
  // The drawing veiled, the parts tinted over it.
  Character over;
  over.width = ch.width;
  over.height = ch.height;
  SubShape veil;
  veil.points = {{0, 0}, {ch.width, 0}, {ch.width, ch.height}, {0, ch.height}};
  veil.contours.push_back({0, 4, true});
  veil.fill.enabled = true;
  veil.fill.color = Rgba{1, 1, 1, 1};
  veil.fill.opacity = 0.55f;
  over.shapes.push_back(veil);
  for (const AutoRigLeftOut& l : ar.left_out)
    if (size_t(l.shape) < ch.shapes.size()) over.shapes.push_back(tint(ch.shapes[size_t(l.shape)], Rgba{0.45, 0.45, 0.45, 1}, 2 * unit, true));
  size_t limb = 0;
  for (const AutoRigPart& p : ar.parts) {
    if (size_t(p.shape) >= ch.shapes.size()) continue;
    const SubShape& s = ch.shapes[size_t(p.shape)];
    if (p.kind == AutoRigPart::Body) over.shapes.push_back(tint(s, Rgba{0.15, 0.25, 0.75, 1}, 3 * unit, true));
    if (p.kind == AutoRigPart::Head) over.shapes.push_back(tint(s, Rgba{0.85, 0.65, 0.0, 1}, 3 * unit, true));
    if (p.kind == AutoRigPart::Limb) over.shapes.push_back(tint(s, hue(limb++), 3 * unit, s.fill.enabled));
  }
  // each limb's axis, from its free end to its hinge
  for (const AutoRigPart& p : ar.parts) {
    if (p.kind != AutoRigPart::Limb || p.path.size() < 2) continue;
    SubShape axis;
    axis.points = p.path;
    axis.contours.push_back({0, int(p.path.size()), false});
    axis.stroke.enabled = true;
    axis.stroke.color = Rgba{0.1, 0.1, 0.1, 0.7};
    axis.stroke.width = 1.2 * unit;
    over.shapes.push_back(axis);
  }
  build_draw_list(over, prepare_mesh(over), {}, view, 0.25, list);
  std::vector<Vec2> handles, hinges;
  for (const RigHandle& hd : ar.rig.handles) handles.push_back(hd.rest);
  for (const AutoRigPart& p : ar.parts)
    if (p.has_joint) hinges.push_back(p.joint);
  append_markers(handles, hinges, -1, view, list);
  if (std::string e = c.draw(list); !e.empty()) return path + ": " + e;
  const std::vector<std::uint8_t> px = c.read_premultiplied();
  Image img = downsample_premultiplied(px.data(), w, h, 1);
  // The names and the legend, drawn by SDL's software renderer with the HUD's font.
  SDL_Surface* surface = SDL_CreateRGBSurfaceWithFormatFrom(img.rgba.data(), w, h, 32, 4 * w, SDL_PIXELFORMAT_ABGR8888);
  SDL_Renderer* r = surface ? SDL_CreateSoftwareRenderer(surface) : nullptr;
  if (r) {
    const std::string font = default_font_path();
    auto atlas = font.empty() ? Result<std::unique_ptr<GlyphAtlas>>::failure("no font") : GlyphAtlas::load(r, font, 12);
    if (atlas.ok()) {
      const GlyphAtlas& f = **atlas.value;
      SDL_SetRenderDrawBlendMode(r, SDL_BLENDMODE_BLEND);
      for (size_t k = 0; k < handles.size(); ++k) {
        const Vec2 at = view.apply(handles[k]);
        const std::string& name = ar.rig.handles[k].name;
        const SDL_Rect box{int(at.x()) + 8, int(at.y()) - 8, f.width(name) + 4, f.line_height() + 2};
        SDL_SetRenderDrawColor(r, 255, 255, 255, 200);
        SDL_RenderFillRect(r, &box);
        f.draw(r, box.x + 2, box.y + 1, name, SDL_Color{0, 100, 45, 255});
      }
      SDL_SetRenderDrawColor(r, 245, 245, 242, 255);
      const SDL_Rect panel{0, dh, w, legend};
      SDL_RenderFillRect(r, &panel);
      for (size_t k = 0; k < lines.size(); ++k) f.draw(r, 8, dh + 5 + int(k) * line_h, lines[k], SDL_Color{30, 30, 30, 255});
    }
    SDL_RenderPresent(r);
    SDL_DestroyRenderer(r);
  }
  if (surface) SDL_FreeSurface(surface);
  if (std::string e = write_png(path, img); !e.empty()) return e;
  return {};
}

}  // namespace mar
