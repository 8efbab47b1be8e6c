// Gradients (character/svg_loader.h): a linearGradient or radialGradient fill or stroke is
// evaluated at load into a texture over the shape's rest bounds (a stroke's widened by half its
// width), sampled through the shape's mesh as an
// <image> is: it deforms with the shape in every renderer and output. Attributes and stops are
// inherited along href chains (16 hops at most); objectBoundingBox and userSpaceOnUse units,
// gradientTransform, spreadMethod pad, reflect and repeat, the focal point of a radial one
// (moved just inside its circle when outside, as SVG 1.1 says), and stop-opacity.
#include "character/svg_loader_impl.h"

#include <algorithm>
#include <cmath>

namespace mar::svg_load {
namespace {


// The colour at t (after the spread), interpolated between the stops (not premultiplied).
Rgba stop_color(const std::vector<GradientStop>& stops, double t) {
  if (t <= stops.front().offset) return stops.front().color;
  if (t >= stops.back().offset) return stops.back().color;
  for (size_t k = 1; k < stops.size(); ++k) {
    const GradientStop &a = stops[k - 1], &b = stops[k];
    if (t > b.offset) continue;
    const double span = b.offset - a.offset;
    const float u = span > 1e-12 ? float((t - a.offset) / span) : 1.0f;
    return {a.color.r + u * (b.color.r - a.color.r), a.color.g + u * (b.color.g - a.color.g),
            a.color.b + u * (b.color.b - a.color.b), a.color.a + u * (b.color.a - a.color.a)};
  }
  return stops.back().color;
}

double spread(double t, std::string_view method) {
  if (!std::isfinite(t)) return 0;
  if (method == "repeat") return t - std::floor(t);
  if (method == "reflect") {
    const double m = std::fmod(std::fabs(t), 2.0);
    return m > 1 ? 2 - m : m;
  }
  return std::clamp(t, 0.0, 1.0);
}

}  // namespace

std::vector<pugi::xml_node> SvgLoader::href_chain(const pugi::xml_node& first, std::initializer_list<std::string_view> kinds) const {
  std::vector<pugi::xml_node> chain;
  for (pugi::xml_node g = first; g && chain.size() < 16; g = lookup_iri(href_of(g))) {
    if (std::find(chain.begin(), chain.end(), g) != chain.end()) break;
    if (std::find(kinds.begin(), kinds.end(), local_name(g)) == kinds.end()) break;
    chain.push_back(g);
  }
  return chain;
}

pugi::xml_node SvgLoader::chain_node(const std::vector<pugi::xml_node>& chain, const char* name) {
  for (const pugi::xml_node& g : chain)
    if (g.attribute(name)) return g;
  return {};
}

std::vector<GradientStop> SvgLoader::gradient_stops(const std::vector<pugi::xml_node>& chain, const Rgba& current) {
  std::vector<GradientStop> stops;
  for (const pugi::xml_node& g : chain) {
    for (pugi::xml_node s : g.children()) {
      if (s.type() != pugi::node_element || local_name(s) != "stop") continue;
      const Decls d = declarations(s);
      GradientStop st;
      if (auto v = prop(d, "stop-color")) {
        if (trim_space(*v) == "currentColor") st.color = current;
        else if (auto pc = parse_color(*v)) st.color = *pc;
      }
      if (auto v = prop(d, "stop-opacity")) st.color.a *= static_cast<float>(svg::parse_opacity(*v, 1));
      const std::string_view off = trim_space(s.attribute("offset").value());
      const double o = !off.empty() && off.back() == '%' ? svg::parse_number(off.substr(0, off.size() - 1)).value_or(0) / 100.0
                                                         : svg::parse_number(off).value_or(0);
      st.offset = std::clamp(o, 0.0, 1.0);
      if (!stops.empty()) st.offset = std::max(st.offset, stops.back().offset);  // (never backwards)
      stops.push_back(st);
    }
    if (!stops.empty()) break;
  }
  return stops;
}

std::shared_ptr<const Texture> SvgLoader::gradient_texture(const pugi::xml_node& server, const Ctx& ctx,
                                                         std::span<const Vec2> points, double pad, Affine2& uv) {
  const std::string_view kind = local_name(server);
  const bool radial = kind == "radialGradient";
  if (!radial && kind != "linearGradient") return nullptr;
  // The chain: this gradient, then what it names by href. An attribute is the first one set
  // along it; the stops are those of the first one that has any.
  const std::vector<pugi::xml_node> chain = href_chain(server, {"linearGradient", "radialGradient"});
  auto attr = [&](const char* name) { return chain_node(chain, name).attribute(name); };
  const std::vector<GradientStop> stops = gradient_stops(chain, ctx.style.color);
  if (stops.empty() || points.empty()) return nullptr;
  // The shape's rest bounds (character units), widened for a stroke: where the texture lies.
  Bounds b;
  for (const Vec2& p : points) b.add(p);
  if (b.empty() || !(b.hi - b.lo).allFinite() || !std::isfinite(pad)) return nullptr;
  b.lo -= Vec2(pad, pad);
  b.hi += Vec2(pad, pad);
  // Gradient space -> character: the element's CTM, the bounding box (objectBoundingBox units:
  // the box of the shape in its own user space), then gradientTransform.
  const Affine2 to_user = ctx.ctm.inverse();
  Bounds ub;
  for (const Vec2& p : points) ub.add(to_user.apply(p));
  const bool bbox_units = std::string_view(attr("gradientUnits").value()) != "userSpaceOnUse";
  Affine2 g_to_char = ctx.ctm;
  if (bbox_units) {
    const Vec2 size = ub.hi - ub.lo;
    if (!(size.x() > 0) || !(size.y() > 0)) return nullptr;  // a line's box has no area: SVG draws nothing
    g_to_char = g_to_char * Affine2{size.x(), 0, 0, size.y(), ub.lo.x(), ub.lo.y()};
  }
  if (pugi::xml_attribute t = attr("gradientTransform")) {
    if (auto m = svg::parse_transform(t.value()); m && m->is_finite())
      g_to_char = g_to_char * about_origin(chain_node(chain, "gradientTransform"), *m);  // (its transform-origin too)
  }
  if (!(std::abs(g_to_char.det()) > 0)) return nullptr;
  const Affine2 char_to_g = g_to_char.inverse();
  // Lengths: fractions of the box (objectBoundingBox: "50%" or 0.5), else user units with % of
  // the viewport.
  auto length = [&](const char* name, int axis, double fallback_fraction) {
    pugi::xml_attribute a = attr(name);
    if (!a) return bbox_units ? fallback_fraction : fallback_fraction * (axis == 0 ? ctx.vp.w : axis == 1 ? ctx.vp.h : std::hypot(ctx.vp.w, ctx.vp.h) / std::sqrt(2.0));
    const std::string_view v = trim_space(a.value());
    if (bbox_units) {
      if (!v.empty() && v.back() == '%') return svg::parse_number(v.substr(0, v.size() - 1)).value_or(0) / 100.0;
      return svg::parse_number(v).value_or(fallback_fraction);
    }
    return svg::parse_length(v, axis, ctx.vp.w, ctx.vp.h).value_or(0.0);
  };
  const std::string spread_method = attr("spreadMethod").value();
  Vec2 p1, p2, c, f;
  double r = 0;
  if (radial) {
    c = {length("cx", 0, 0.5), length("cy", 1, 0.5)};
    r = length("r", 2, 0.5);
    f = {attr("fx") ? length("fx", 0, 0.5) : c.x(), attr("fy") ? length("fy", 1, 0.5) : c.y()};
    if (!(r > 0)) return nullptr;  // r = 0: the last stop's colour (said by the caller's fallback)
    if ((f - c).norm() > 0.999 * r) f = c + (f - c) * (0.999 * r / (f - c).norm());
  } else {
    p1 = {length("x1", 0, 0.0), length("y1", 1, 0.0)};
    p2 = {length("x2", 0, 1.0), length("y2", 1, 0.0)};
  }
  // The texture: about two texels a character unit, 8 to 256 a side.
  const Vec2 size = b.hi - b.lo;
  if (!(size.x() > 0) || !(size.y() > 0)) return nullptr;  // (a shape with no area shows no gradient)
  // (clamped as doubles: a drawing 1e60 wide is not an int)
  const int tw = int(std::clamp(std::ceil(size.x() * 2), 8.0, 256.0)), th = int(std::clamp(std::ceil(size.y() * 2), 8.0, 256.0));
  auto tex = std::make_shared<Texture>();
  tex->name = std::string("gradient ") + server.attribute("id").value();
  tex->width = tw;
  tex->height = th;
  tex->rgba.resize(size_t(tw) * size_t(th) * 4);
  const Vec2 d = p2 - p1;
  const double dd = d.squaredNorm();
  for (int y = 0; y < th; ++y)
    for (int x = 0; x < tw; ++x) {
      const Vec2 p = char_to_g.apply(Vec2(b.lo.x() + (x + 0.5) * size.x() / tw, b.lo.y() + (y + 0.5) * size.y() / th));
      double t = 0;
      if (radial) {
        // The circle through p in the family from the focal point (t = 0) to the circle (t = 1).
        const Vec2 v = p - f, w = f - c;
        const double A = v.squaredNorm(), B = 2 * v.dot(w), C = w.squaredNorm() - r * r;
        const double disc = B * B - 4 * A * C;
        const double s = A > 0 ? (-B + std::sqrt(std::max(0.0, disc))) / (2 * A) : 0;
        t = s > 0 ? 1.0 / s : 0;
      } else {
        t = dd > 0 ? (p - p1).dot(d) / dd : 1;  // x1,y1 = x2,y2: the last stop's colour
      }
      const Rgba col = stop_color(stops, spread(t, spread_method));
      uint8_t* o = &tex->rgba[(size_t(y) * size_t(tw) + size_t(x)) * 4];
      const float comp[4] = {col.r, col.g, col.b, col.a};
      for (int k = 0; k < 4; ++k) o[k] = uint8_t(std::lround(std::clamp(comp[k], 0.0f, 1.0f) * 255.0f));
    }
  uv = Affine2{1.0 / size.x(), 0, 0, 1.0 / size.y(), -b.lo.x() / size.x(), -b.lo.y() / size.y()};
  return tex;
}

std::shared_ptr<const Texture> SvgLoader::gradient_paint(const Paint& p, const pugi::xml_node& n, const Ctx& ctx,
                                                       std::span<const Vec2> points, double pad, Affine2& uv) {
  if (p.kind != Paint::Url) return nullptr;
  const pugi::xml_node server = lookup_iri(p.url);
  const std::string_view k = server ? local_name(server) : std::string_view{};
  if (k != "linearGradient" && k != "radialGradient") return nullptr;
  if (gradient_texels_ >= opt_.max_gradient_texels) {
    warn(n, "more gradients than the texture budget (" + std::to_string(opt_.max_gradient_texels) +
                " texels); drawn as its mean colour");
    return nullptr;
  }
  auto tex = gradient_texture(server, ctx, points, pad, uv);
  if (tex) gradient_texels_ += size_t(tex->width) * size_t(tex->height);
  return tex;
}

// Patterns: the tiles that cover the shape, each a copy of the pattern's content placed by x, y,
// width, height (patternUnits both ways), viewBox or patternContentUnits, and
// patternTransform; attributes and content inherited along href chains. They are shapes of a
// layer clipped by the shape (Character::composites), so the pattern deforms with it. Tiles
// are not clipped to their own box (overflow is taken as visible).
bool SvgLoader::pattern_fill(const pugi::xml_node& server, const pugi::xml_node& n, const Ctx& ctx, const SubShape& s) {
  const std::vector<pugi::xml_node> chain = href_chain(server, {"pattern"});
  auto attr = [&](const char* name) { return chain_node(chain, name).attribute(name); };
  pugi::xml_node content;
  for (const pugi::xml_node& g : chain) {
    for (pugi::xml_node c : g.children())
      if (c.type() == pugi::node_element) {
        content = g;
        break;
      }
    if (content) break;
  }
  if (!content || s.points.empty()) return false;
  if (layer_depth_ >= kMaxLayerDepth) {
    warn(n, "a pattern inside layers nested deeper than " + std::to_string(kMaxLayerDepth) + "; painted as its colour");
    return false;
  }
  if (std::find(use_stack_.begin(), use_stack_.end(), server) != use_stack_.end() || use_stack_.size() > 32) {
    warn(n, "a pattern drawn inside itself; painted as its colour");
    return false;
  }
  const Style& st = ctx.style;
  const Affine2 to_user = ctx.ctm.inverse();
  Bounds ub;
  for (const Vec2& p : s.points) ub.add(to_user.apply(p));
  if (ub.empty() || !(ub.hi - ub.lo).allFinite()) return false;
  const bool bbox_units = std::string_view(attr("patternUnits").value()) != "userSpaceOnUse";
  const bool content_bbox = std::string_view(attr("patternContentUnits").value()) == "objectBoundingBox";
  // x, y, width, height: fractions of the shape's box (objectBoundingBox), else user lengths.
  auto value = [&](const char* name, int axis) {
    const std::string_view v = trim_space(attr(name).value());
    if (!bbox_units) return svg::parse_length(v, axis, ctx.vp.w, ctx.vp.h).value_or(0.0);
    if (!v.empty() && v.back() == '%') return svg::parse_number(v.substr(0, v.size() - 1)).value_or(0) / 100.0;
    return svg::parse_number(v).value_or(0.0);
  };
  double x = value("x", 0), y = value("y", 1), w = value("width", 0), h = value("height", 1);
  if (bbox_units) {
    x = ub.lo.x() + x * ub.width();
    y = ub.lo.y() + y * ub.height();
    w *= ub.width();
    h *= ub.height();
  }
  if (!(w > 0) || !(h > 0) || !std::isfinite(x + y + w + h)) return false;
  Affine2 pt;
  if (pugi::xml_node g = chain_node(chain, "patternTransform"))  // (its transform-origin too)
    if (auto t = svg::parse_transform(g.attribute("patternTransform").value()); t && t->is_finite()) pt = about_origin(g, *t);
  Affine2 inner;
  Viewport vp{w, h};
  if (auto vb = svg::parse_viewbox(attr("viewBox").value()); vb && (*vb)[2] > 0 && (*vb)[3] > 0) {
    inner = svg::viewbox_transform(*vb, w, h, attr("preserveAspectRatio").value());
    vp = {(*vb)[2], (*vb)[3]};
  } else if (content_bbox) {
    if (!(ub.width() > 0) || !(ub.height() > 0)) return false;
    inner = Affine2::scale(ub.width(), ub.height());
  }
  // The tiles that cover the shape: its bounds in the pattern's space.
  const Affine2 to_pattern = (ctx.ctm * pt).inverse();
  Bounds pb;
  for (const Vec2& p : s.points) pb.add(to_pattern.apply(p));
  if (pb.empty() || !(pb.hi - pb.lo).allFinite()) return false;
  const double i0 = std::floor((pb.lo.x() - x) / w), i1 = std::ceil((pb.hi.x() - x) / w);
  const double j0 = std::floor((pb.lo.y() - y) / h), j1 = std::ceil((pb.hi.y() - y) / h);
  if (!((i1 - i0) * (j1 - j0) <= 256)) {
    warn(n, std::string("pattern '") + server.attribute("id").value() + "' would take more than 256 tiles to cover it; painted as its colour");
    count(ch_.approximated, "a pattern of too many tiles painted as a colour");
    return false;
  }
  Composite c;
  c.id = s.id + ":pattern";
  c.opacity = static_cast<float>(std::clamp(st.fill_opacity * st.group_opacity, 0.0, 1.0));
  c.first = static_cast<int>(ch_.shapes.size());
  const int ci = static_cast<int>(ch_.composites.size());
  ch_.composites.push_back(std::move(c));
  Ctx pc = ctx;
  pc.style = compute_style(content, Style{});
  pc.vp = vp;
  pc.depth = ctx.depth + 1;
  pc.id_prefix = ctx.id_prefix + s.id + ":pattern:";
  use_stack_.push_back(server);
  ++layer_depth_;
  for (double i = i0; i < i1 && fatal_.empty(); ++i)
    for (double j = j0; j < j1 && fatal_.empty(); ++j) {
      pc.ctm = ctx.ctm * pt * Affine2::translate(x + i * w, y + j * h) * inner;
      for (pugi::xml_node k : content.children()) visit(k, pc);
    }
  --layer_depth_;
  use_stack_.pop_back();
  ch_.composites[size_t(ci)].end = static_cast<int>(ch_.shapes.size());
  // The shape itself clips its tiles.
  SubShape clip = s;
  clip.id = s.id + ":pattern-clip";
  clip.role = ShapeRole::Clip;
  clip.owner = ci;
  clip.fill = Fill{};
  clip.fill.enabled = true;
  clip.fill.color = Rgba{1, 1, 1, 1};
  clip.fill.rule = st.fill_rule;
  clip.stroke = Stroke{};
  clip.layer = layer_index(ctx);
  ch_.composites[size_t(ci)].clip.push_back(static_cast<int>(ch_.shapes.size()));
  ch_.shapes.push_back(std::move(clip));
  return true;
}

}  // namespace mar::svg_load
