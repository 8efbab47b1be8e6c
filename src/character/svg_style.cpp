// The SVG loader's cascade (svg_loader_impl.h): presentation attributes, CSS rules and the
// style attribute, paint, and what shows.
#include "character/svg_loader_impl.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace mar::svg_load {

// Cascade: presentation attributes < CSS rules (by specificity, then order) < the style
// attribute < CSS !important. The last declaration of a property wins in prop().
SvgLoader::Decls SvgLoader::declarations(const pugi::xml_node& n) const {
  Decls d;
  static const char* kPresentation[] = {
      "fill", "fill-opacity", "fill-rule", "stroke", "stroke-width", "stroke-opacity",
      "stroke-linejoin", "stroke-linecap", "stroke-miterlimit", "opacity", "display",
      "visibility", "color", "stop-color", "stop-opacity", "stroke-dasharray", "filter",
      "mask", "clip-path", "stroke-dashoffset", "paint-order", "vector-effect", "marker-start", "marker-mid",
      "marker-end", "clip-rule", "mask-type", "overflow", "font-size", "font-family", "font-weight", "font-style",
      "text-anchor", "letter-spacing"};
  for (const char* p : kPresentation) {
    if (pugi::xml_attribute a = n.attribute(p)) d.emplace_back(p, a.value());
  }
  std::vector<const css::Rule*> matched;
  if (!sheet_.rules.empty()) {
    const std::string_view tag = local_name(n), id = n.attribute("id").value(),
                           cls = n.attribute("class").value();
    for (const css::Rule& r : sheet_.rules) {
      if (css::matches(r.selector, tag, id, cls)) matched.push_back(&r);
    }
    std::stable_sort(matched.begin(), matched.end(), [](const css::Rule* a, const css::Rule* b) {
      return a->selector.specificity != b->selector.specificity
                 ? a->selector.specificity < b->selector.specificity
                 : a->order < b->order;
    });
    for (const css::Rule* r : matched) d.insert(d.end(), r->declarations.begin(), r->declarations.end());
  }
  Decls important;
  const Decls inline_decls = css::parse_declarations(n.attribute("style").value(), &important);
  d.insert(d.end(), inline_decls.begin(), inline_decls.end());
  for (const css::Rule* r : matched) d.insert(d.end(), r->important.begin(), r->important.end());
  d.insert(d.end(), important.begin(), important.end());
  return d;
}

void SvgLoader::collect_style_sheets(const pugi::xml_node& root) {
  for (const pugi::xpath_node& xn : root.select_nodes("//*")) {
    const pugi::xml_node n = xn.node();
    if (local_name(n) != "style") continue;
    const std::string_view type = n.attribute("type").value();
    if (!type.empty() && type != "text/css") continue;
    std::string text;
    for (pugi::xml_node c : n.children()) {
      if (c.type() == pugi::node_pcdata || c.type() == pugi::node_cdata) text += c.value();
    }
    const size_t before = sheet_.unsupported.size();
    css::parse(text, sheet_);
    for (size_t i = before; i < sheet_.unsupported.size(); ++i) {
      warn(n, "CSS selector '" + sheet_.unsupported[i] + "' not supported; rule skipped");
    }
  }
}

std::optional<std::string_view> SvgLoader::prop(const Decls& d, std::string_view key) {
  std::optional<std::string_view> v;
  for (const auto& [k, val] : d) {
    if (k == key) v = val;
  }
  return v;
}

std::optional<Paint> SvgLoader::parse_paint(std::string_view v, const pugi::xml_node& n) {
  v = trim_space(v);
  Paint p;
  if (v == "none") return Paint{};
  if (v == "currentColor") {
    p.kind = Paint::CurrentColor;
    return p;
  }
  if (v.rfind("url(", 0) == 0) {
    p.kind = Paint::Url;
    const size_t close = v.find(')');
    p.url = std::string(v.substr(0, close == std::string_view::npos ? v.size() : close + 1));
    if (close != std::string_view::npos) {
      std::string_view fb = trim_space(v.substr(close + 1));
      if (fb == "none") {
        p.has_fallback = p.fallback_none = true;
      } else if (auto c = parse_color(fb)) {
        p.has_fallback = true;
        p.fallback = *c;
      }
    }
    return p;
  }
  if (auto c = parse_color(v)) {
    p.kind = Paint::Color;
    p.color = *c;
    return p;
  }
  warn(n, "cannot parse paint '" + std::string(v) + "'; ignored");
  return std::nullopt;
}

double SvgLoader::length_attr(const pugi::xml_node& n, const char* attr, int axis, const Viewport& vp,
                              double fallback) {
  pugi::xml_attribute a = n.attribute(attr);
  if (!a) return fallback;
  auto v = svg::parse_length(a.value(), axis, vp.w, vp.h, current_font_);
  if (!v) {
    warn(n, std::string("bad length ") + attr + "=\"" + a.value() + "\"");
    return fallback;
  }
  return *v;
}

Style SvgLoader::compute_style(const pugi::xml_node& n, const Style& parent) {
  Style s = parent;
  const Decls d = declarations(n);
  // (the CSS transform property, for element_transform, read with the rest)
  css_transform_of_ = n;
  const auto declared_transform = prop(d, "transform");
  css_transform_ = declared_transform ? std::optional<std::string>(std::string(*declared_transform)) : std::nullopt;
  auto is_inherit = [](std::string_view v) { return trim_space(v) == "inherit"; };
  if (auto v = prop(d, "font-size"); v && !is_inherit(*v)) {  // (em and % of the parent's)
    const std::string_view f = trim_space(*v);
    if (!f.empty() && f.back() == '%') {
      if (auto k = svg::parse_length(f.substr(0, f.size() - 1), 0, 0, 0); k && *k > 0) s.font_size = parent.font_size * *k / 100;
    } else if (auto k = svg::parse_length(f, 2, current_vp_.w, current_vp_.h, parent.font_size); k && *k > 0 && *k < 1e6) {
      s.font_size = *k;
    }
  }
  current_font_ = s.font_size;
  if (auto v = prop(d, "font-family"); v && !is_inherit(*v) && !trim_space(*v).empty()) s.font_family = std::string(trim_space(*v));
  if (auto v = prop(d, "font-weight"); v && !is_inherit(*v)) {
    const std::string_view w = trim_space(*v);
    if (w == "normal") s.font_weight = 400;
    else if (w == "bold") s.font_weight = 700;
    else if (w == "bolder") s.font_weight = parent.font_weight < 350 ? 400 : parent.font_weight < 550 ? 700 : 900;
    else if (w == "lighter") s.font_weight = parent.font_weight < 550 ? 100 : parent.font_weight < 750 ? 400 : 700;
    else if (auto k = svg::parse_length(w, 0, 0, 0); k && *k >= 1 && *k <= 1000) s.font_weight = int(*k);
  }
  if (auto v = prop(d, "font-style"); v && !is_inherit(*v)) {
    const std::string_view f = trim_space(*v);
    s.italic = f == "italic" || f.rfind("oblique", 0) == 0;
  }
  if (auto v = prop(d, "text-anchor"); v && !is_inherit(*v)) {
    const std::string_view a = trim_space(*v);
    s.text_anchor = a == "middle" ? 1 : a == "end" ? 2 : 0;
  }
  if (auto v = prop(d, "letter-spacing"); v && !is_inherit(*v)) {
    const std::string_view l = trim_space(*v);
    if (l == "normal") s.letter_spacing = 0;
    else if (auto k = svg::parse_length(l, 0, current_vp_.w, current_vp_.h, s.font_size); k && std::abs(*k) < 1e6) s.letter_spacing = *k;
  }
  if (pugi::xml_attribute a = n.attribute("xml:space")) s.preserve_space = std::string_view(a.value()) == "preserve";
  if (auto v = prop(d, "color"); v && !is_inherit(*v)) {
    if (auto c = parse_color(*v)) s.color = *c;
  }
  if (auto v = prop(d, "fill"); v && !is_inherit(*v)) {
    if (auto p = parse_paint(*v, n)) {
      s.fill = *p;
      s.fill_current = p->kind == Paint::CurrentColor;
    }
  }
  if (auto v = prop(d, "stroke"); v && !is_inherit(*v)) {
    if (auto p = parse_paint(*v, n)) {
      s.stroke = *p;
      s.stroke_current = p->kind == Paint::CurrentColor;
    }
  }
  // currentColor is inherited as the keyword and resolved against each element's own color
  // (a group's fill="currentColor" over a child's color="green" paints green).
  if (s.fill_current) s.fill = Paint{Paint::Color, s.color, {}, false, {}, false};
  if (s.stroke_current) s.stroke = Paint{Paint::Color, s.color, {}, false, {}, false};
  if (auto v = prop(d, "fill-opacity"); v && !is_inherit(*v)) s.fill_opacity = svg::parse_opacity(*v, 1);
  if (auto v = prop(d, "stroke-opacity"); v && !is_inherit(*v)) s.stroke_opacity = svg::parse_opacity(*v, 1);
  if (auto v = prop(d, "clip-rule"); v) {
    if (trim_space(*v) == "evenodd") s.clip_rule = FillRule::EvenOdd;
    if (trim_space(*v) == "nonzero") s.clip_rule = FillRule::NonZero;
  }
  if (auto v = prop(d, "fill-rule"); v) {
    if (trim_space(*v) == "evenodd") s.fill_rule = FillRule::EvenOdd;
    if (trim_space(*v) == "nonzero") s.fill_rule = FillRule::NonZero;
  }
  if (auto v = prop(d, "stroke-width"); v && !is_inherit(*v)) {
    Viewport vp = current_vp_;
    if (auto w = svg::parse_length(*v, 2, vp.w, vp.h, current_font_); w && *w >= 0) s.stroke_width = *w;
  }
  if (auto v = prop(d, "stroke-linejoin"); v) {
    const std::string_view j = trim_space(*v);
    if (j == "miter" || j == "miter-clip" || j == "arcs") s.join = LineJoin::Miter;
    if (j == "round") s.join = LineJoin::Round;
    if (j == "bevel") s.join = LineJoin::Bevel;
  }
  if (auto v = prop(d, "stroke-linecap"); v) {
    const std::string_view j = trim_space(*v);
    if (j == "butt") s.cap = LineCap::Butt;
    if (j == "round") s.cap = LineCap::Round;
    if (j == "square") s.cap = LineCap::Square;
  }
  if (auto v = prop(d, "stroke-miterlimit"); v) {
    if (auto m = svg::parse_number(*v); m && *m >= 1) s.miter_limit = *m;
  }
  if (auto v = prop(d, "visibility"); v) {
    const std::string_view j = trim_space(*v);
    if (j == "hidden" || j == "collapse") s.visible = false;
    if (j == "visible") s.visible = true;
  }
  if (auto v = prop(d, "opacity"); v) s.group_opacity *= svg::parse_opacity(*v, 1);
  if (auto v = prop(d, "stroke-dasharray"); v && !is_inherit(*v)) {
    // Lengths (user units, % of the viewport's diagonal), by commas or spaces; an odd list is
    // repeated; none, all zeros or a negative length draw the stroke solid (SVG 2, 13.5.1).
    std::vector<double> dashes;
    const std::vector<std::string_view> items = trim_space(*v) == "none" ? std::vector<std::string_view>{} : svg::split_list(*v, 65);
    bool bad = items.size() > 64;
    for (size_t k = 0; k < items.size() && !bad; ++k) {
      const auto len = svg::parse_length(items[k], 2, current_vp_.w, current_vp_.h);
      bad = !len || !(*len >= 0);
      if (!bad) dashes.push_back(*len);
    }
    double sum = 0;
    for (double x : dashes) sum += x;
    if (bad) warn(n, "stroke-dasharray=\"" + std::string(*v) + "\" is not a list of at most 64 lengths of 0 or more; drawn solid");
    if (bad || !(sum > 0)) dashes.clear();
    if (dashes.size() % 2) dashes.insert(dashes.end(), dashes.begin(), dashes.end());
    s.dashes = std::move(dashes);
  }
  if (auto v = prop(d, "stroke-dashoffset"); v && !is_inherit(*v)) {
    if (auto o = svg::parse_length(*v, 2, current_vp_.w, current_vp_.h); o && std::isfinite(*o)) s.dash_offset = *o;
  }
  if (auto v = prop(d, "paint-order"); v && !is_inherit(*v)) {
    // "stroke" before "fill" (or named with fill left out: "stroke markers" puts fill last).
    const std::string_view o = trim_space(*v);
    const size_t st = o.find("stroke"), fi = o.find("fill");
    s.stroke_first = o != "normal" && st != std::string_view::npos && (fi == std::string_view::npos || st < fi);
  }
  // Markers: the `marker` shorthand (style sheets and the style attribute only), then each.
  for (const auto& [k, v] : d) {
    std::string* slot = k == "marker-start" ? &s.marker_start : k == "marker-mid" ? &s.marker_mid : k == "marker-end" ? &s.marker_end : nullptr;
    if (k == "marker" && !n.attribute("marker")) {
      s.marker_start = s.marker_mid = s.marker_end = std::string(trim_space(v));
    } else if (slot && !is_inherit(v)) {
      *slot = std::string(trim_space(v));
    }
  }
  s.non_scaling = false;
  if (auto v = prop(d, "vector-effect"); v) s.non_scaling = trim_space(*v) == "non-scaling-stroke";
  return s;
}

// A hidden child of a group of alternatives: an element with display: none whose parent is a
// group (not a layer) with a child that shows (a hand's poses, one visible). It is kept,
// hidden until a swap set shows it; other hidden content (a hidden layer, a sketch) is not.
bool SvgLoader::alternative(const pugi::xml_node& n) {
  const pugi::xml_node g = n.parent();
  if (local_name(g) != "g" || std::string_view(g.attribute("inkscape:groupmode").value()) == "layer") return false;
  if (std::string_view(n.attribute("inkscape:groupmode").value()) == "layer") return false;
  for (pugi::xml_node c : g.children())
    if (c != n && c.type() == pugi::node_element && local_name(c).find(':') == std::string_view::npos && visible_element(c)) return true;
  return false;
}

bool SvgLoader::visible_element(const pugi::xml_node& n) {
  const Decls d = declarations(n);
  if (auto v = prop(d, "display"); v && trim_space(*v) == "none") return false;
  return true;
}

// Representative solid colour for a paint server, with a warning.
std::optional<Rgba> SvgLoader::paint_server_color(const pugi::xml_node& server, const pugi::xml_node& user,
                                                  const Style& st) {
  const std::string_view kind = local_name(server);
  if (kind == "linearGradient" || kind == "radialGradient") {
    const std::vector<GradientStop> stops = gradient_stops(href_chain(server, {"linearGradient", "radialGradient"}), st.color);
    if (stops.empty()) {  // no stops: painted as none (SVG), said
      warn(user, std::string(kind) + " '" + server.attribute("id").value() + "' has no stops; painted as none");
      paint_failed_ = true;
      return std::nullopt;
    }
    Rgba mean{0, 0, 0, 0};
    for (const auto& [offset, c] : stops) {
      mean.r += c.r;
      mean.g += c.g;
      mean.b += c.b;
      mean.a += c.a;
    }
    const float k = 1.0f / static_cast<float>(stops.size());
    mean = {mean.r * k, mean.g * k, mean.b * k, mean.a * k};
    if (stops.size() > 1) {
      warn(user, std::string(kind) + " '" + server.attribute("id").value() +
                     "' drawn as its mean colour " + color_hex(mean));
      count(ch_.approximated, "a gradient drawn as its mean colour");
    }
    return mean;
  }
  if (kind == "pattern") {
    Rgba c{0.5f, 0.5f, 0.5f, 1};
    for (const pugi::xpath_node& d : server.select_nodes(".//*[@fill]")) {
      if (auto pc = parse_color(d.node().attribute("fill").value())) {
        c = *pc;
        break;
      }
    }
    warn(user, std::string("pattern '") + server.attribute("id").value() + "' drawn as solid " +
                   color_hex(c));
    count(ch_.approximated, "a pattern drawn as a solid colour");
    return c;
  }
  warn(user, "paint server <" + std::string(kind) + "> not supported; drawn as none");
  paint_failed_ = true;
  return std::nullopt;
}

// Resolves a paint to a colour (alpha included); nullopt = nothing drawn.
std::optional<Rgba> SvgLoader::resolve(const Paint& p, const pugi::xml_node& user, const Style& st) {
  switch (p.kind) {
    case Paint::None:
      return std::nullopt;
    case Paint::Color:
      return p.color;
    case Paint::CurrentColor:
      return st.color;
    case Paint::Url: {
      pugi::xml_node server = lookup_iri(p.url);
      if (!server) {
        if (p.has_fallback && !p.fallback_none) return p.fallback;
        if (!p.has_fallback) {
          warn(user, "paint " + p.url + " not found; drawn as none");
          paint_failed_ = true;
        }
        return std::nullopt;
      }
      return paint_server_color(server, user, st);
    }
  }
  return std::nullopt;
}

}  // namespace mar::svg_load
