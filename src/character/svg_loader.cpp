// Loading an SVG character (character/svg_loader.h): parsing, bookkeeping, viewports and the
// traversal. The cascade is in svg_style.cpp, shapes and images in svg_geometry.cpp.
#include "character/svg_loader_impl.h"

#include "geom/polygon.h"
#include "base/read_file.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <sstream>

namespace mar::svg_load {

Result<Character> SvgLoader::run(std::string_view text) {
  text_ = text;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\n') line_starts_.push_back(i + 1);
  }
  pugi::xml_parse_result pr =
      doc_.load_buffer(text.data(), text.size(), pugi::parse_default | pugi::parse_ws_pcdata_single,
                       pugi::encoding_auto);
  if (!pr) {
    return Result<Character>::failure(name_ + ":" + std::to_string(line_of(static_cast<size_t>(pr.offset))) +
                                      ": malformed XML: " + pr.description());
  }
  pugi::xml_node root = doc_.document_element();
  resolve_namespaces(root);
  if (!root || local_name(root) != "svg") {
    return Result<Character>::failure(name_ + ":" + std::to_string(root ? line_of(root) : 1) +
                                      ": root element is <" + std::string(root ? root.name() : "") +
                                      ">, not <svg>");
  }
  index_ids(root);
  collect_style_sheets(root);
  ch_.source = name_;

  Ctx ctx;
  const auto vb = svg::parse_viewbox(root.attribute("viewBox").value());
  Viewport outer{vb ? (*vb)[2] : 100.0, vb ? (*vb)[3] : 100.0};
  double w = length_attr(root, "width", 0, outer, vb ? (*vb)[2] : 100.0);
  double h = length_attr(root, "height", 1, outer, vb ? (*vb)[3] : 100.0);
  if (!(w > 0) || !std::isfinite(w)) w = vb ? (*vb)[2] : 100.0;
  if (!(h > 0) || !std::isfinite(h)) h = vb ? (*vb)[3] : 100.0;
  ch_.width = w;
  ch_.height = h;
  ctx.vp = vb ? Viewport{(*vb)[2], (*vb)[3]} : Viewport{w, h};
  ctx.style = compute_style(root, ctx.style);
  ctx.ctm = vb ? svg::viewbox_transform(*vb, w, h, root.attribute("preserveAspectRatio").value())
               : Affine2::identity();
  if (!visible_element(root)) return Result<Character>::success(std::move(ch_));
  for (pugi::xml_node c : root.children()) {
    visit(c, ctx);
    if (!fatal_.empty()) return Result<Character>::failure(fatal_);
  }
  make_ids_unique();
  return Result<Character>::success(std::move(ch_));
}

int SvgLoader::line_of(size_t offset) const {
  auto it = std::upper_bound(line_starts_.begin(), line_starts_.end(), offset);
  return static_cast<int>(it - line_starts_.begin());  // starts <= offset = 1-based line
}

int SvgLoader::line_of(const pugi::xml_node& n) const {
  const ptrdiff_t off = n.offset_debug();
  return off < 0 ? 0 : line_of(static_cast<size_t>(off));
}

std::string SvgLoader::where(const pugi::xml_node& n) const {
  std::string s = name_ + ":" + std::to_string(line_of(n)) + ": <" + std::string(local_name(n));
  if (const char* id = n.attribute("id").value(); *id) s += std::string(" id=\"") + id + "\"";
  return s + ">";
}

void SvgLoader::warn(const pugi::xml_node& n, const std::string& msg) {
  std::string w = where(n) + ": " + msg;
  if (warned_.insert(w).second && ch_.warnings.size() < 200) ch_.warnings.push_back(std::move(w));
}

void SvgLoader::resolve_namespaces(const pugi::xml_node& root) {
  static constexpr std::string_view kSvgNs = "http://www.w3.org/2000/svg";
  // Depth first with the declarations in scope: (prefix, namespace), innermost last; "" is the
  // default namespace. A file that declares none is SVG throughout (hand-written files often
  // leave xmlns out), and so is an undeclared "svg:" prefix.
  struct Frame {
    pugi::xml_node n;
    size_t scope;  // the scope's size when n was entered
  };
  std::vector<std::pair<std::string_view, std::string_view>> scope;
  std::vector<Frame> stack{{root, 0}};
  while (!stack.empty()) {
    const Frame f = stack.back();
    stack.pop_back();
    scope.resize(f.scope);
    for (pugi::xml_attribute a : f.n.attributes()) {
      const std::string_view an = a.name();
      if (an == "xmlns") scope.emplace_back("", a.value());
      else if (an.rfind("xmlns:", 0) == 0) scope.emplace_back(an.substr(6), a.value());
    }
    const std::string_view name = f.n.name();
    const size_t colon = name.find(':');
    const std::string_view prefix = colon == std::string_view::npos ? std::string_view() : name.substr(0, colon);
    std::optional<std::string_view> uri;
    for (auto it = scope.rbegin(); it != scope.rend(); ++it)
      if (it->first == prefix) {
        uri = it->second;
        break;
      }
    const bool svg = uri ? *uri == kSvgNs : (prefix.empty() || prefix == "svg");
    ns_skip_[f.n.internal_object()] = svg ? uint16_t(prefix.empty() ? 0 : colon + 1) : kForeign;
    const size_t here = scope.size();
    for (pugi::xml_node c = f.n.last_child(); c; c = c.previous_sibling())
      if (c.type() == pugi::node_element) stack.push_back({c, here});
  }
}

// Element name without the SVG namespace's prefix; foreign names keep theirs (see the header).
std::string_view SvgLoader::local_name(const pugi::xml_node& n) const {
  std::string_view s = n.name();
  const auto it = ns_skip_.find(n.internal_object());
  if (it == ns_skip_.end()) return s;
  if (it->second != kForeign) return s.substr(std::min<size_t>(it->second, s.size()));
  return s.find(':') != std::string_view::npos ? s : std::string_view("foreign:element");
}

pugi::xml_node SvgLoader::child_named(const pugi::xml_node& n, std::string_view local) const {
  for (pugi::xml_node c : n.children())
    if (c.type() == pugi::node_element && local_name(c) == local) return c;
  return {};
}

void SvgLoader::index_ids(const pugi::xml_node& root) {
  std::vector<pugi::xml_node> stack{root};
  while (!stack.empty()) {
    pugi::xml_node n = stack.back();
    stack.pop_back();
    if (const char* id = n.attribute("id").value(); *id) ids_.try_emplace(id, n);
    for (pugi::xml_node c = n.last_child(); c; c = c.previous_sibling()) {
      if (c.type() == pugi::node_element) stack.push_back(c);
    }
  }
}

pugi::xml_node SvgLoader::lookup_iri(std::string_view ref) const {
  ref = trim_space(ref);
  if (ref.rfind("url(", 0) == 0) {
    ref.remove_prefix(4);
    const size_t close = ref.find(')');
    if (close != std::string_view::npos) ref = ref.substr(0, close);
    ref = trim_space(ref);
    if (!ref.empty() && (ref.front() == '\'' || ref.front() == '"')) ref = ref.substr(1, ref.size() - 2);
  }
  if (ref.empty() || ref[0] != '#') return {};
  auto it = ids_.find(std::string(ref.substr(1)));
  return it == ids_.end() ? pugi::xml_node{} : it->second;
}

const char* SvgLoader::href_of(const pugi::xml_node& n) {
  if (const char* h = n.attribute("href").value(); *h) return h;  // (SVG 2: href over xlink:href)
  return n.attribute("xlink:href").value();
}

// transform-origin (SVG 2, CSS): x and y as lengths, percentages of the viewport (the view-box
// reference box) or keywords, in either order where the keywords say which is which.
std::optional<Vec2> SvgLoader::transform_origin(const pugi::xml_node& n) {
  std::string value = n.attribute("transform-origin").value();
  if (const std::string_view style = n.attribute("style").value(); style.find("transform-origin") != std::string_view::npos)
    for (const auto& [k, v] : css::parse_declarations(style, nullptr))
      if (k == "transform-origin") value = v;
  std::vector<std::string_view> parts = svg::split_list(value, 3);
  if (parts.empty()) return std::nullopt;
  auto vertical = [](std::string_view k) { return k == "top" || k == "bottom"; };
  auto horizontal = [](std::string_view k) { return k == "left" || k == "right"; };
  // One value: x, or y when it can only be y; two: x then y, unless the keywords say otherwise.
  if (parts.size() == 1) {
    if (vertical(parts[0])) parts.insert(parts.begin(), "center");
    else parts.push_back("center");
  } else if (vertical(parts[0]) || horizontal(parts[1])) {
    std::swap(parts[0], parts[1]);
  }
  auto coord = [&](std::string_view v, int axis) -> std::optional<double> {
    const double size = axis == 0 ? current_vp_.w : current_vp_.h;
    if (v == "center") return 0.5 * size;
    if (v == "left" || v == "top") return 0.0;
    if (v == "right" || v == "bottom") return size;
    return svg::parse_length(v, axis, current_vp_.w, current_vp_.h);
  };
  const auto x = coord(parts[0], 0), y = coord(parts[1], 1);
  if (!x || !y || !std::isfinite(*x) || !std::isfinite(*y)) {
    warn(n, "bad transform-origin \"" + value + "\"; ignored");
    return std::nullopt;
  }
  return Vec2(*x, *y);
}

Affine2 SvgLoader::element_transform(const pugi::xml_node& n) {
  // The CSS property (a style attribute's or a sheet's) over the attribute; its lengths and
  // angles may carry units (translate(10px, 5px), rotate(45deg)): those of the attribute's.
  // (compute_style, just before, read it with the element's declarations: not matched again)
  std::optional<std::string> declared = css_transform_;
  if (css_transform_of_ != n) {
    const Decls d = declarations(n);
    const auto v = prop(d, "transform");
    declared = v ? std::optional<std::string>(std::string(*v)) : std::nullopt;
  }
  std::string text;
  const bool css = declared.has_value();
  for (size_t i = 0; css && i < declared->size(); ++i) {
    const std::string_view v = *declared;
    const bool after_number = i > 0 && (std::isdigit(static_cast<unsigned char>(v[i - 1])) || v[i - 1] == '.');
    if (after_number && v.substr(i, 2) == "px") {
      ++i;
      continue;
    }
    if (after_number && v.substr(i, 3) == "deg") {
      i += 2;
      continue;
    }
    text.push_back(v[i]);
  }
  pugi::xml_attribute t = n.attribute("transform");
  if (!css && !t) return Affine2::identity();
  if (!css) text = t.value();
  if (trim_space(text) == "none") return Affine2::identity();
  auto m = svg::parse_transform(text);
  if (!m || !m->is_finite()) {
    warn(n, "bad transform \"" + text + "\"; element not drawn");
    return Affine2{0, 0, 0, 0, 0, 0};
  }
  return about_origin(n, *m);
}

void SvgLoader::visit(const pugi::xml_node& n, const Ctx& parent) {
  if (n.type() != pugi::node_element || !fatal_.empty()) return;
  const std::string_view name = local_name(n);
  if (++elements_ > opt_.max_elements) {
    fatal_ = where(n) + ": more than " + std::to_string(opt_.max_elements) +
             " elements once <use> references are expanded (markers and pattern tiles count too; the limit); file refused";
    return;
  }
  if (parent.depth > 200) {
    warn(n, "nesting deeper than 200 levels; skipped");
    return;
  }
  static const std::set<std::string_view> kSilent = {
      "defs", "symbol", "clipPath", "mask", "marker", "linearGradient", "radialGradient",
      "pattern", "filter", "title", "desc", "metadata", "script", "font", "font-face",
      "cursor", "view", "animate", "animateTransform", "animateMotion", "animateColor", "set",
      "stop"};
  if (kSilent.count(name)) return;
  if (name.find(':') != std::string_view::npos) return;  // foreign namespace (sodipodi, ...)
  // Conditional processing holds everywhere, not only in a switch: an element for another
  // language (systemLanguage) or an extension we lack is not drawn.
  if (!passes_conditions(n)) return;
  bool hidden = parent.hidden;
  if (!visible_element(n)) {
    if (!alternative(n)) return;
    hidden = true;
  }

  Ctx ctx = parent;
  ctx.hidden = hidden;
  ctx.depth = parent.depth + 1;
  current_vp_ = parent.vp;
  ctx.style = compute_style(n, parent.style);
  ctx.ctm = parent.ctm * element_transform(n);
  // Drawn as one layer (opacity, filter, clip-path, mask: svg_composite.cpp)? Its content is
  // what this element draws below; its clip and mask come after.
  const int composite = begin_composite(n, parent, ctx);
  if (composite >= 0) ++layer_depth_;

  if (name == "g" || name == "a") {
    const bool inkscape_layer = std::string_view(n.attribute("inkscape:groupmode").value()) == "layer";
    if (inkscape_layer || (parent.depth == 0 && name == "g")) {
      ctx.layer_key = static_cast<int>(n.offset_debug());
      const char* label = n.attribute("inkscape:label").value();
      const char* id = n.attribute("id").value();
      ctx.layer_name = *label ? label : (*id ? id : "layer-L" + std::to_string(line_of(n)));
    }
    {
      const char* label = n.attribute("inkscape:label").value();
      const char* gid = n.attribute("id").value();
      const std::string gname = *label ? label : *gid ? gid : "g-L" + std::to_string(line_of(n));
      ctx.group = parent.group.empty() ? gname : parent.group + "/" + gname;
      ctx.group_key = static_cast<int>(n.offset_debug());
    }
    for (pugi::xml_node c : n.children()) visit(c, ctx);
  } else if (name == "svg") {
    visit_nested_svg(n, ctx, n, 0, 0, false);
  } else if (name == "switch") {
    static constexpr std::string_view kDrawn[] = {"g", "svg", "path", "rect", "circle", "ellipse", "line", "polyline",
                                                  "polygon", "image", "use", "text", "foreignObject", "switch", "a"};
    for (pugi::xml_node c : n.children()) {
      if (c.type() != pugi::node_element) continue;
      // (an element SVG does not know is no alternative: the next one is)
      if (std::find(std::begin(kDrawn), std::end(kDrawn), local_name(c)) == std::end(kDrawn)) continue;
      if (passes_conditions(c)) {
        visit(c, ctx);
        break;
      }
    }
  } else if (name == "use") {
    visit_use(n, ctx);
  } else if (name == "path" || name == "rect" || name == "circle" || name == "ellipse" ||
             name == "line" || name == "polyline" || name == "polygon") {
    shape(n, ctx);
  } else if (name == "text") {
    text(n, ctx);
  } else if (name == "image") {
    image(n, ctx);
  } else if (name == "style") {
    // applied through the cascade (collect_style_sheets)
  } else if (name == "foreignObject") {
    warn(n, "foreignObject skipped");
  } else {
    warn(n, "unsupported element skipped");
  }
  if (composite >= 0) {
    --layer_depth_;
    end_composite(composite, n, ctx);
  }
}

bool SvgLoader::passes_conditions(const pugi::xml_node& c) {
  // We implement no extensions, and an empty list evaluates to false as well.
  if (c.attribute("requiredExtensions")) return false;
  if (pugi::xml_attribute lang = c.attribute("systemLanguage")) return svg::system_language_matches(lang.value());
  return true;
}

// Nested <svg> (or a <symbol>/<svg> instanced by <use>): a new viewport.
void SvgLoader::visit_nested_svg(const pugi::xml_node& n, Ctx ctx, const pugi::xml_node& content,
                                 double use_w, double use_h, bool from_use, const std::array<double, 4>* viewbox,
                                 const char* par) {
  // (a use places its own x and y; an svg it draws keeps its x and y inside that)
  const bool own_xy = !from_use || local_name(content) == "svg";
  const double x = own_xy ? length_attr(from_use ? content : n, "x", 0, ctx.vp, 0) : 0;
  const double y = own_xy ? length_attr(from_use ? content : n, "y", 1, ctx.vp, 0) : 0;
  double w = use_w > 0 ? use_w : length_attr(content, "width", 0, ctx.vp, ctx.vp.w);
  double h = use_h > 0 ? use_h : length_attr(content, "height", 1, ctx.vp, ctx.vp.h);
  if (!(w > 0) || !(h > 0)) return;  // zero-size viewport draws nothing
  ctx.ctm = ctx.ctm * Affine2::translate(x, y);
  const Affine2 port = ctx.ctm;  // (the viewport's own space: [0, w] x [0, h])
  auto vb = svg::parse_viewbox(content.attribute("viewBox").value());
  if (viewbox) vb = *viewbox;
  if (vb) {
    ctx.ctm = ctx.ctm * svg::viewbox_transform(*vb, w, h, par ? par : content.attribute("preserveAspectRatio").value());
    ctx.vp = {(*vb)[2], (*vb)[3]};
  } else {
    ctx.vp = {w, h};
  }
  // The viewport clips what it holds (overflow: hidden, the default for svg and symbol): a layer
  // clipped by its rectangle, kept only where something crosses it.
  const Decls decls = declarations(content);
  const auto overflow = prop(decls, "overflow");
  const std::string_view o = overflow ? trim_space(*overflow) : std::string_view{};
  const bool clips = ctx.role == ShapeRole::Paint && o != "visible" && o != "auto" && layer_depth_ < kMaxLayerDepth;
  const size_t first = ch_.shapes.size(), comps = ch_.composites.size();
  if (clips) {
    Composite c;
    c.id = std::string(local_name(content)) + "-L" + std::to_string(line_of(content));
    c.first = static_cast<int>(first);
    ch_.composites.push_back(std::move(c));
  }
  if (clips) ++layer_depth_;
  for (pugi::xml_node c : content.children()) visit(c, ctx);
  if (!clips) return;
  --layer_depth_;
  Composite& comp = ch_.composites[comps];
  comp.end = static_cast<int>(ch_.shapes.size());
  const Affine2 to_port = port.inverse();
  bool crosses = false;
  for (size_t k = first; k < ch_.shapes.size() && !crosses; ++k)
    for (const Vec2& p : ch_.shapes[k].points) {
      const Vec2 q = to_port.apply(p);
      const double slack = 1e-6 * (w + h);
      if (!(q.x() >= -slack && q.y() >= -slack && q.x() <= w + slack && q.y() <= h + slack)) {
        crosses = true;
        break;
      }
    }
  if (!crosses) {  // (nothing to clip: no layer; one that nests others stays, and is drawn straight)
    if (ch_.composites.size() == comps + 1) ch_.composites.pop_back();
    return;
  }
  SubShape r;
  r.id = comp.id + ":viewport";
  r.element = "viewport";
  r.line = line_of(content);
  r.role = ShapeRole::Clip;
  r.owner = static_cast<int>(comps);
  r.points = {port.apply(Vec2(0, 0)), port.apply(Vec2(w, 0)), port.apply(Vec2(w, h)), port.apply(Vec2(0, h))};
  r.contours = {{0, 4, true}};
  r.fill.enabled = true;
  r.fill.color = Rgba{1, 1, 1, 1};
  r.layer = layer_index(ctx);
  comp.clip.push_back(static_cast<int>(ch_.shapes.size()));
  ch_.shapes.push_back(std::move(r));
}

void SvgLoader::visit_use(const pugi::xml_node& n, Ctx ctx) {
  pugi::xml_node target = lookup_iri(href_of(n));
  if (!target) {
    warn(n, std::string("use of missing element '") + href_of(n) + "'; skipped");
    return;
  }
  for (pugi::xml_node a = n; a; a = a.parent()) {
    if (a == target) {
      warn(n, "use refers to its own ancestor; skipped");
      return;
    }
  }
  if (std::find(use_stack_.begin(), use_stack_.end(), target) != use_stack_.end() ||
      use_stack_.size() > 32) {
    warn(n, "recursive use; skipped");
    return;
  }
  const double x = length_attr(n, "x", 0, ctx.vp, 0);
  const double y = length_attr(n, "y", 1, ctx.vp, 0);
  ctx.ctm = ctx.ctm * Affine2::translate(x, y);
  if (const char* id = n.attribute("id").value(); *id) ctx.id_prefix += std::string(id) + ":";
  use_stack_.push_back(target);
  const std::string_view tname = local_name(target);
  if (tname == "symbol" || tname == "svg") {
    const double w = length_attr(n, "width", 0, ctx.vp, 0);
    const double h = length_attr(n, "height", 1, ctx.vp, 0);
    if (visible_element(target)) {
      Ctx inner = ctx;
      current_vp_ = ctx.vp;
      inner.style = compute_style(target, ctx.style);
      // (a symbol's transform is SVG 2's; SVG 1.1, which the drawings and resvg's suite follow, has none)
      inner.ctm = tname == "svg" ? ctx.ctm * element_transform(target) : ctx.ctm;
      inner.depth = ctx.depth + 1;
      visit_nested_svg(target, inner, target, w > 0 ? w : 0, h > 0 ? h : 0, true);
    }
  } else {
    visit(target, ctx);
  }
  use_stack_.pop_back();
}

}  // namespace mar::svg_load

namespace mar {

Result<Character> load_svg_string(std::string_view text, const std::string& name,
                                  const SvgOptions& options) {
  svg_load::SvgLoader loader(name, options);
  return loader.run(text);
}

Result<Character> load_svg_file(const std::string& path, const SvgOptions& options) {
  Result<std::string> read = read_file(path, options.max_bytes, "an SVG character");
  if (!read.ok()) return Result<Character>::failure(read.error);
  const std::string& text = *read.value;
  if (text.empty()) return Result<Character>::failure(path + ":1: empty file");
  return load_svg_string(text, path, options);
}

}  // namespace mar
