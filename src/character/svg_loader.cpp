#include "character/svg_loader.h"

#include "character/color.h"
#include "character/css.h"
#include "character/svg_parse.h"
#include "geom/polygon.h"
#include "input/read_file.h"

#include <pugixml.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <unordered_map>

namespace mar {
namespace {

using svg::PathCmd;

struct Paint {
  enum Kind { None, Color, CurrentColor, Url } kind = None;
  Rgba color;
  std::string url;
  bool has_fallback = false;
  Rgba fallback;
  bool fallback_none = false;
};

// Inherited properties, plus the accumulated (non-inherited) opacity of ancestors.
struct Style {
  Paint fill{Paint::Color, Rgba{0, 0, 0, 1}, {}, false, {}, false};
  double fill_opacity = 1;
  FillRule fill_rule = FillRule::NonZero;
  Paint stroke;
  double stroke_opacity = 1;
  double stroke_width = 1;
  LineJoin join = LineJoin::Miter;
  LineCap cap = LineCap::Butt;
  double miter_limit = 4;
  Rgba color{0, 0, 0, 1};
  bool visible = true;
  double group_opacity = 1;  // product of ancestors' opacity
};

struct Viewport {
  double w = 100, h = 100;
};

struct Ctx {
  Affine2 ctm;
  Style style;
  Viewport vp;
  int layer_key = -1;  // offset of the layer's <g>, -1 = root
  std::string layer_name = "(root)";
  std::string id_prefix;
  std::string group;  // the enclosing groups' names (label, else id), outermost first, '/' between
  int group_key = -1; // offset of the innermost <g>, -1 = none
  bool hidden = false; // inside an alternative hidden with display: none (see alternative())
  int depth = 0;
};

class SvgLoader {
 public:
  SvgLoader(const std::string& name, const SvgOptions& opt) : name_(name), opt_(opt) {}

  Result<Character> run(std::string_view text) {
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
    detect_svg_prefix(root);
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

 private:
  // ---- bookkeeping -------------------------------------------------------------------
  int line_of(size_t offset) const {
    auto it = std::upper_bound(line_starts_.begin(), line_starts_.end(), offset);
    return static_cast<int>(it - line_starts_.begin());  // starts <= offset = 1-based line
  }
  int line_of(const pugi::xml_node& n) const {
    const ptrdiff_t off = n.offset_debug();
    return off < 0 ? 0 : line_of(static_cast<size_t>(off));
  }
  std::string where(const pugi::xml_node& n) const {
    std::string s = name_ + ":" + std::to_string(line_of(n)) + ": <" + std::string(local_name(n));
    if (const char* id = n.attribute("id").value(); *id) s += std::string(" id=\"") + id + "\"";
    return s + ">";
  }
  void warn(const pugi::xml_node& n, const std::string& msg) {
    std::string w = where(n) + ": " + msg;
    if (warned_.insert(w).second && ch_.warnings.size() < 200) ch_.warnings.push_back(std::move(w));
  }

  void detect_svg_prefix(const pugi::xml_node& root) {
    for (pugi::xml_attribute a : root.attributes()) {
      std::string_view an = a.name();
      if (an.rfind("xmlns:", 0) == 0 && std::string_view(a.value()) == "http://www.w3.org/2000/svg") {
        svg_prefix_ = std::string(an.substr(6)) + ":";
      }
    }
  }
  // Element name without the SVG namespace prefix; foreign-namespace names keep theirs.
  std::string_view local_name(const pugi::xml_node& n) const {
    std::string_view s = n.name();
    if (!svg_prefix_.empty() && s.rfind(svg_prefix_, 0) == 0) s.remove_prefix(svg_prefix_.size());
    return s;
  }

  void index_ids(const pugi::xml_node& root) {
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

  pugi::xml_node lookup_iri(std::string_view ref) const {
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

  static const char* href_of(const pugi::xml_node& n) {
    if (const char* h = n.attribute("xlink:href").value(); *h) return h;
    return n.attribute("href").value();
  }

  // ---- properties ------------------------------------------------------------------
  using Decls = std::vector<std::pair<std::string, std::string>>;

  // Cascade: presentation attributes < CSS rules (by specificity, then order) < the style
  // attribute < CSS !important. The last declaration of a property wins in prop().
  Decls declarations(const pugi::xml_node& n) const {
    Decls d;
    static const char* kPresentation[] = {
        "fill", "fill-opacity", "fill-rule", "stroke", "stroke-width", "stroke-opacity",
        "stroke-linejoin", "stroke-linecap", "stroke-miterlimit", "opacity", "display",
        "visibility", "color", "stop-color", "stop-opacity", "stroke-dasharray", "filter",
        "mask", "clip-path"};
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

  void collect_style_sheets(const pugi::xml_node& root) {
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

  static std::optional<std::string_view> prop(const Decls& d, std::string_view key) {
    std::optional<std::string_view> v;
    for (const auto& [k, val] : d) {
      if (k == key) v = val;
    }
    return v;
  }

  std::optional<Paint> parse_paint(std::string_view v, const pugi::xml_node& n) {
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

  double length_attr(const pugi::xml_node& n, const char* attr, int axis, const Viewport& vp,
                     double fallback) {
    pugi::xml_attribute a = n.attribute(attr);
    if (!a) return fallback;
    auto v = svg::parse_length(a.value(), axis, vp.w, vp.h);
    if (!v) {
      warn(n, std::string("bad length ") + attr + "=\"" + a.value() + "\"");
      return fallback;
    }
    return *v;
  }

  Style compute_style(const pugi::xml_node& n, const Style& parent) {
    Style s = parent;
    const Decls d = declarations(n);
    auto is_inherit = [](std::string_view v) { return trim_space(v) == "inherit"; };
    if (auto v = prop(d, "color"); v && !is_inherit(*v)) {
      if (auto c = parse_color(*v)) s.color = *c;
    }
    if (auto v = prop(d, "fill"); v && !is_inherit(*v)) {
      if (auto p = parse_paint(*v, n)) s.fill = *p;
    }
    if (auto v = prop(d, "stroke"); v && !is_inherit(*v)) {
      if (auto p = parse_paint(*v, n)) s.stroke = *p;
    }
    // currentColor is resolved where it is specified (inherited as a colour).
    if (s.fill.kind == Paint::CurrentColor) s.fill = Paint{Paint::Color, s.color, {}, false, {}, false};
    if (s.stroke.kind == Paint::CurrentColor) s.stroke = Paint{Paint::Color, s.color, {}, false, {}, false};
    if (auto v = prop(d, "fill-opacity"); v && !is_inherit(*v)) s.fill_opacity = svg::parse_opacity(*v, 1);
    if (auto v = prop(d, "stroke-opacity"); v && !is_inherit(*v)) s.stroke_opacity = svg::parse_opacity(*v, 1);
    if (auto v = prop(d, "fill-rule"); v) {
      if (trim_space(*v) == "evenodd") s.fill_rule = FillRule::EvenOdd;
      if (trim_space(*v) == "nonzero") s.fill_rule = FillRule::NonZero;
    }
    if (auto v = prop(d, "stroke-width"); v && !is_inherit(*v)) {
      Viewport vp = current_vp_;
      if (auto w = svg::parse_length(*v, 2, vp.w, vp.h); w && *w >= 0) s.stroke_width = *w;
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
    if (auto v = prop(d, "stroke-dasharray"); v && trim_space(*v) != "none") {
      warn(n, "stroke-dasharray is not supported; drawn solid");
    }
    if (auto v = prop(d, "filter"); v && trim_space(*v) != "none") warn(n, "filter ignored");
    if (auto v = prop(d, "mask"); v && trim_space(*v) != "none") warn(n, "mask ignored");
    if (auto v = prop(d, "clip-path"); v && trim_space(*v) != "none") warn(n, "clip-path ignored");
    return s;
  }

  // A hidden child of a group of alternatives: an element with display: none whose parent is a
  // group (not a layer) with a child that shows (a hand's poses, one visible). It is kept,
  // hidden until a swap set shows it; other hidden content (a hidden layer, a sketch) is not.
  bool alternative(const pugi::xml_node& n) {
    const pugi::xml_node g = n.parent();
    if (local_name(g) != "g" || std::string_view(g.attribute("inkscape:groupmode").value()) == "layer") return false;
    if (std::string_view(n.attribute("inkscape:groupmode").value()) == "layer") return false;
    for (pugi::xml_node c : g.children())
      if (c != n && c.type() == pugi::node_element && local_name(c).find(':') == std::string_view::npos && visible_element(c)) return true;
    return false;
  }

  bool visible_element(const pugi::xml_node& n) {
    const Decls d = declarations(n);
    if (auto v = prop(d, "display"); v && trim_space(*v) == "none") return false;
    return true;
  }

  // Representative solid colour for a paint server, with a warning.
  std::optional<Rgba> paint_server_color(const pugi::xml_node& server, const pugi::xml_node& user,
                                         const Style& st) {
    const std::string_view kind = local_name(server);
    if (kind == "linearGradient" || kind == "radialGradient") {
      pugi::xml_node g = server;
      for (int hops = 0; hops < 16 && g; ++hops) {
        if (g.child(qualified("stop").c_str())) break;
        g = lookup_iri(href_of(g));
      }
      std::vector<Rgba> stops;
      if (g) {
        for (pugi::xml_node s : g.children()) {
          if (local_name(s) != "stop") continue;
          const Decls d = declarations(s);
          Rgba c{0, 0, 0, 1};
          if (auto v = prop(d, "stop-color")) {
            if (trim_space(*v) == "currentColor") {
              c = st.color;
            } else if (auto pc = parse_color(*v)) {
              c = *pc;
            }
          }
          if (auto v = prop(d, "stop-opacity")) c.a *= static_cast<float>(svg::parse_opacity(*v, 1));
          stops.push_back(c);
        }
      }
      if (stops.empty()) return std::nullopt;  // no stops: painted as none
      Rgba mean{0, 0, 0, 0};
      for (const Rgba& c : stops) {
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
      return c;
    }
    warn(user, "paint server <" + std::string(kind) + "> not supported; drawn as none");
    return std::nullopt;
  }

  std::string qualified(const char* local) const { return svg_prefix_ + local; }

  // Resolves a paint to a colour (alpha included); nullopt = nothing drawn.
  std::optional<Rgba> resolve(const Paint& p, const pugi::xml_node& user, const Style& st) {
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
          if (!p.has_fallback) warn(user, "paint " + p.url + " not found; drawn as none");
          return std::nullopt;
        }
        return paint_server_color(server, user, st);
      }
    }
    return std::nullopt;
  }

  // ---- viewports ---------------------------------------------------------------------
  Affine2 element_transform(const pugi::xml_node& n) {
    pugi::xml_attribute t = n.attribute("transform");
    if (!t) return Affine2::identity();
    auto m = svg::parse_transform(t.value());
    if (!m || !m->is_finite()) {
      warn(n, std::string("bad transform \"") + t.value() + "\"; element not drawn");
      return Affine2{0, 0, 0, 0, 0, 0};
    }
    return *m;
  }

  // ---- traversal ---------------------------------------------------------------------
  void visit(const pugi::xml_node& n, const Ctx& parent) {
    if (n.type() != pugi::node_element || !fatal_.empty()) return;
    const std::string_view name = local_name(n);
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
      for (pugi::xml_node c : n.children()) {
        if (c.type() != pugi::node_element) continue;
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
      warn(n, "text is not supported; skipped");
    } else if (name == "image") {
      image(n, ctx);
    } else if (name == "style") {
      // applied through the cascade (collect_style_sheets)
    } else if (name == "foreignObject") {
      warn(n, "foreignObject skipped");
    } else {
      warn(n, "unsupported element skipped");
    }
  }

  bool passes_conditions(const pugi::xml_node& c) {
    // We implement no extensions, and an empty list evaluates to false as well.
    if (c.attribute("requiredExtensions")) return false;
    if (pugi::xml_attribute lang = c.attribute("systemLanguage")) return svg::system_language_matches(lang.value());
    return true;
  }

  // Nested <svg> (or a <symbol>/<svg> instanced by <use>): a new viewport.
  void visit_nested_svg(const pugi::xml_node& n, Ctx ctx, const pugi::xml_node& content,
                        double use_w, double use_h, bool from_use) {
    const double x = from_use ? 0 : length_attr(n, "x", 0, ctx.vp, 0);
    const double y = from_use ? 0 : length_attr(n, "y", 1, ctx.vp, 0);
    double w = use_w > 0 ? use_w : length_attr(content, "width", 0, ctx.vp, ctx.vp.w);
    double h = use_h > 0 ? use_h : length_attr(content, "height", 1, ctx.vp, ctx.vp.h);
    if (!(w > 0) || !(h > 0)) return;  // zero-size viewport draws nothing
    ctx.ctm = ctx.ctm * Affine2::translate(x, y);
    const auto vb = svg::parse_viewbox(content.attribute("viewBox").value());
    if (vb) {
      ctx.ctm = ctx.ctm * svg::viewbox_transform(*vb, w, h, content.attribute("preserveAspectRatio").value());
      ctx.vp = {(*vb)[2], (*vb)[3]};
    } else {
      ctx.vp = {w, h};
    }
    for (pugi::xml_node c : content.children()) visit(c, ctx);
  }

  void visit_use(const pugi::xml_node& n, Ctx ctx) {
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
        inner.ctm = ctx.ctm * element_transform(target);
        inner.depth = ctx.depth + 1;
        visit_nested_svg(target, inner, target, w > 0 ? w : 0, h > 0 ? h : 0, true);
      }
    } else {
      visit(target, ctx);
    }
    use_stack_.pop_back();
  }

  // ---- geometry ----------------------------------------------------------------------
  void shape(const pugi::xml_node& n, const Ctx& ctx) {
    const std::string_view name = local_name(n);
    std::vector<PathCmd> cmds;
    auto move = [&](Vec2 p) { cmds.push_back(PathCmd::to(PathCmd::Move, p)); };
    auto line = [&](Vec2 p) { cmds.push_back(PathCmd::to(PathCmd::Line, p)); };
    auto close = [&](Vec2 p) { cmds.push_back(PathCmd::to(PathCmd::Close, p)); };
    const Viewport& vp = ctx.vp;
    if (name == "path") {
      svg::PathData pd = svg::parse_path(n.attribute("d").value(), points_left());
      if (pd.too_long) {
        return too_complex(n);
      }
      if (!pd.error.empty()) {
        warn(n, "path data error at character " + std::to_string(pd.error_pos) + ": " + pd.error +
                    " (drawn up to there)");
      }
      cmds = std::move(pd.cmds);
    } else if (name == "rect") {
      const double x = length_attr(n, "x", 0, vp, 0), y = length_attr(n, "y", 1, vp, 0);
      const double w = length_attr(n, "width", 0, vp, 0), h = length_attr(n, "height", 1, vp, 0);
      if (!(w > 0) || !(h > 0)) return;
      double rx = -1, ry = -1;
      if (n.attribute("rx")) rx = length_attr(n, "rx", 0, vp, -1);
      if (n.attribute("ry")) ry = length_attr(n, "ry", 1, vp, -1);
      if (rx < 0 && ry >= 0) rx = ry;
      if (ry < 0 && rx >= 0) ry = rx;
      cmds = svg::rect_path(x, y, w, h, std::clamp(rx, 0.0, w / 2), std::clamp(ry, 0.0, h / 2));
    } else if (name == "circle" || name == "ellipse") {
      const double cx = length_attr(n, "cx", 0, vp, 0), cy = length_attr(n, "cy", 1, vp, 0);
      double rx, ry;
      if (name == "circle") {
        rx = ry = length_attr(n, "r", 2, vp, 0);
      } else {
        rx = length_attr(n, "rx", 0, vp, -1);
        ry = length_attr(n, "ry", 1, vp, -1);
        if (rx < 0 && ry > 0) rx = ry;  // SVG 2 "auto"
        if (ry < 0 && rx > 0) ry = rx;
      }
      if (!(rx > 0) || !(ry > 0)) return;
      cmds = svg::ellipse_path(cx, cy, rx, ry);
    } else if (name == "line") {
      move({length_attr(n, "x1", 0, vp, 0), length_attr(n, "y1", 1, vp, 0)});
      line({length_attr(n, "x2", 0, vp, 0), length_attr(n, "y2", 1, vp, 0)});
    } else {  // polyline, polygon
      bool odd = false;
      const std::vector<Vec2> pts = svg::parse_points(n.attribute("points").value(), &odd);
      if (odd) warn(n, "odd number of coordinates in points; last one dropped");
      if (pts.size() < 2) return;
      move(pts[0]);
      for (size_t i = 1; i < pts.size(); ++i) line(pts[i]);
      if (name == "polygon") close(pts[0]);
    }
    emit(n, ctx, cmds);
  }

  // ---- images ------------------------------------------------------------------------
  std::shared_ptr<const Texture> load_image(const pugi::xml_node& n, std::string_view href) {
    const std::string key(href);
    if (auto it = images_.find(key); it != images_.end()) return it->second;
    std::string problem;
    auto tex = svg::decode_image_href(href, std::filesystem::path(name_).parent_path().string(), opt_.images_anywhere, problem);
    if (!tex) warn(n, problem + "; skipped");
    return images_[key] = tex;
  }

  // <image>: a textured rectangle placed by x, y, width, height and preserveAspectRatio.
  void image(const pugi::xml_node& n, const Ctx& ctx) {
    if (!ctx.style.visible) return;
    const std::string_view href = trim_space(href_of(n));
    if (href.empty()) return;
    std::shared_ptr<const Texture> tex = load_image(n, href);
    if (!tex) return;
    const double x = length_attr(n, "x", 0, ctx.vp, 0), y = length_attr(n, "y", 1, ctx.vp, 0);
    double w = length_attr(n, "width", 0, ctx.vp, 0), h = length_attr(n, "height", 1, ctx.vp, 0);
    if (!n.attribute("width") && !n.attribute("height")) {
      w = tex->width;
      h = tex->height;
    } else if (!n.attribute("width")) {
      w = h * tex->width / tex->height;
    } else if (!n.attribute("height")) {
      h = w * tex->height / tex->width;
    }
    if (!(w > 0) || !(h > 0)) return;
    // Placement of the whole image inside the viewport (x, y, w, h).
    const Affine2 place = svg::viewbox_transform({0, 0, static_cast<double>(tex->width), static_cast<double>(tex->height)},
                                            w, h, n.attribute("preserveAspectRatio").value());
    const Vec2 i0 = place.apply({0, 0}), i1 = place.apply({static_cast<double>(tex->width), static_cast<double>(tex->height)});
    // The drawn rectangle is the image clipped to its viewport.
    const double x0 = x + std::max(0.0, i0.x()), y0 = y + std::max(0.0, i0.y());
    const double x1 = x + std::min(w, i1.x()), y1 = y + std::min(h, i1.y());
    if (!(x1 > x0) || !(y1 > y0)) return;
    std::vector<PathCmd> cmds{PathCmd::to(PathCmd::Move, {x0, y0}), PathCmd::to(PathCmd::Line, {x1, y0}),
                              PathCmd::to(PathCmd::Line, {x1, y1}), PathCmd::to(PathCmd::Line, {x0, y1}),
                              PathCmd::to(PathCmd::Close, {x0, y0})};
    const double det = ctx.ctm.det();
    if (!std::isfinite(det) || std::abs(det) < 1e-12) return;
    // character point -> user point -> image pixels -> [0, 1]
    const Affine2 uv = Affine2::scale(1.0 / tex->width, 1.0 / tex->height) * place.inverse() *
                       Affine2::translate(-x, -y) * ctx.ctm.inverse();
    Ctx img_ctx = ctx;
    img_ctx.style.fill = Paint{Paint::Color, Rgba{1, 1, 1, 1}, {}, false, {}, false};
    img_ctx.style.fill_opacity = 1;
    img_ctx.style.stroke = Paint{};
    const size_t before = ch_.shapes.size();
    emit(n, img_ctx, cmds);
    if (ch_.shapes.size() > before) {
      ch_.shapes.back().fill.texture = tex;
      ch_.shapes.back().fill.uv_from_point = uv;
    }
  }

  // The point budget (SvgOptions::max_points): what is left of it, and the error past it.
  size_t points_left() const { return opt_.max_points - std::min(opt_.max_points, total_points_); }
  void too_complex(const pugi::xml_node& n) {
    fatal_ = where(n) + ": more than " + std::to_string(opt_.max_points) + " points after flattening; file too complex";
  }

  void emit(const pugi::xml_node& n, const Ctx& ctx, const std::vector<PathCmd>& cmds) {
    const Style& st = ctx.style;
    if (!st.visible || cmds.empty()) return;
    bool over = false;
    const std::vector<svg::FlatContour> flat = svg::flatten_path(cmds, ctx.ctm, opt_.tolerance, points_left(), &over);
    if (over) return too_complex(n);
    SubShape s;
    s.element = std::string(local_name(n));
    s.line = line_of(n);
    const char* id = n.attribute("id").value();
    s.id = ctx.id_prefix + (*id ? std::string(id) : s.element + "-L" + std::to_string(s.line));
    s.label = n.attribute("inkscape:label").value();
    s.group = ctx.group;
    s.group_key = ctx.group_key;
    s.hidden = ctx.hidden;
    for (const svg::FlatContour& fc : flat) {
      Points pts = fc.points;
      for (Vec2& p : pts) {
        if (!p.allFinite()) p = Vec2::Zero();
      }
      remove_duplicate_points(pts, fc.closed);
      if (pts.size() < 2) continue;
      s.contours.push_back({static_cast<int>(s.points.size()), static_cast<int>(pts.size()), fc.closed});
      s.points.insert(s.points.end(), pts.begin(), pts.end());
    }
    if (s.points.empty()) return;
    total_points_ += s.points.size();
    if (total_points_ > opt_.max_points) return too_complex(n);
    const double op = st.group_opacity;
    if (auto c = resolve(st.fill, n, st)) {
      // Lines never fill; other open sub-paths are filled as if closed (SVG rules).
      bool fillable = s.element != "line";
      if (fillable) {
        s.fill.enabled = true;
        s.fill.color = *c;
        s.fill.opacity = static_cast<float>(st.fill_opacity * op);
        s.fill.rule = st.fill_rule;
      }
    }
    if (auto c = resolve(st.stroke, n, st); c && st.stroke_width > 0) {
      s.stroke.enabled = true;
      s.stroke.color = *c;
      s.stroke.opacity = static_cast<float>(st.stroke_opacity * op);
      // Non-uniform scale: use the geometric mean (strokes are not re-shaped per axis).
      s.stroke.width = st.stroke_width * std::sqrt(std::abs(ctx.ctm.det()));
      s.stroke.join = st.join;
      s.stroke.cap = st.cap;
      s.stroke.miter_limit = st.miter_limit;
    }
    if (!s.fill.enabled && !s.stroke.enabled) return;
    if (s.fill.enabled && s.fill.opacity * s.fill.color.a <= 0 &&
        (!s.stroke.enabled || s.stroke.opacity * s.stroke.color.a <= 0)) {
      return;  // fully transparent
    }
    s.layer = layer_index(ctx);
    ch_.shapes.push_back(std::move(s));
  }

  int layer_index(const Ctx& ctx) {
    auto [it, fresh] = layer_ids_.try_emplace(ctx.layer_key, static_cast<int>(ch_.layers.size()));
    if (fresh) ch_.layers.push_back(ctx.layer_name);
    return it->second;
  }

  void make_ids_unique() {
    std::map<std::string, int> seen;
    for (SubShape& s : ch_.shapes) {
      const int k = ++seen[s.id];
      if (k > 1) {
        s.id.push_back('.');
        s.id.append(std::to_string(k));
      }
    }
  }

  std::string name_;
  SvgOptions opt_;
  std::string_view text_;
  std::vector<size_t> line_starts_{0};
  pugi::xml_document doc_;
  std::string svg_prefix_;
  std::unordered_map<std::string, pugi::xml_node> ids_;
  std::vector<pugi::xml_node> use_stack_;
  std::set<std::string> warned_;
  std::map<int, int> layer_ids_;
  css::Sheet sheet_;
  std::map<std::string, std::shared_ptr<const Texture>> images_;
  Viewport current_vp_;
  Character ch_;
  size_t total_points_ = 0;
  std::string fatal_;
};

}  // namespace

Result<Character> load_svg_string(std::string_view text, const std::string& name,
                                  const SvgOptions& options) {
  SvgLoader loader(name, options);
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
