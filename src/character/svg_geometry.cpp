// The SVG loader's geometry (svg_loader_impl.h): shapes to contours, images to textured
// rectangles, layers and unique ids.
#include "character/svg_loader_impl.h"

#include "geom/polygon.h"

#include <algorithm>
#include <filesystem>
#include <functional>
#include <sstream>

namespace mar::svg_load {

void SvgLoader::shape(const pugi::xml_node& n, const Ctx& ctx) {
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
  if (ctx.style.visible && ctx.role != ShapeRole::Clip) markers(n, ctx, cmds);  // (on every shape, as SVG 2 has it)
}

// An <image>'s box: its width and height; where it gives neither (or "auto"), the picture's
// own size (iw x ih); where it gives one, the other keeps the picture's proportions.
void SvgLoader::image_size(const pugi::xml_node& n, const Viewport& vp, double iw, double ih, double& w, double& h) {
  auto given = [&](const char* a) { return n.attribute(a) && trim_space(n.attribute(a).value()) != "auto"; };
  w = given("width") ? length_attr(n, "width", 0, vp, 0) : 0;
  h = given("height") ? length_attr(n, "height", 1, vp, 0) : 0;
  if (!given("width") && !given("height")) {
    w = iw;
    h = ih;
  } else if (!given("width")) {
    w = h * iw / ih;
  } else if (!given("height")) {
    h = w * ih / iw;
  }
}

// <image>: a textured rectangle placed by x, y, width, height and preserveAspectRatio; or, for an
// SVG document, its shapes (svg_image).
void SvgLoader::image(const pugi::xml_node& n, const Ctx& ctx) {
  if (!ctx.style.visible) return;
  const std::string_view href = trim_space(href_of(n));
  if (href.empty()) return;
  const std::string key(href);
  std::shared_ptr<const Texture> tex;
  if (auto it = images_.find(key); it != images_.end()) {
    tex = it->second;
  } else {  // (read once: a raster image is decoded and kept; an SVG document is drawn as one, each time)
    std::vector<unsigned char> bytes;
    std::string label, problem;
    if (svg::image_href_bytes(href, std::filesystem::path(name_).parent_path().string(), opt_.images_anywhere, bytes, label, problem)) {
      if (svg::is_svg_image(href, bytes)) {
        svg_image(n, ctx, bytes, label);
        return;
      }
      tex = svg::decode_image_bytes(bytes, label, problem);
    }
    if (!tex) warn(n, problem + "; skipped");
    images_[key] = tex;
  }
  if (!tex) return;
  const double x = length_attr(n, "x", 0, ctx.vp, 0), y = length_attr(n, "y", 1, ctx.vp, 0);
  double w = 0, h = 0;
  image_size(n, ctx.vp, tex->width, tex->height, w, h);
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

void SvgLoader::too_complex(const pugi::xml_node& n) {
  fatal_ = where(n) + ": more than " + std::to_string(opt_.max_points) + " points after flattening; file too complex";
}

void SvgLoader::emit(const pugi::xml_node& n, const Ctx& ctx, const std::vector<PathCmd>& cmds) {
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
  s.group_is_layer = ctx.group_key >= 0 && ctx.group_key == ctx.layer_key;
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
  if (s.points.size() > opt_.max_shape_points) {
    fatal_ = where(n) + ": one shape of " + std::to_string(s.points.size()) + " points after flattening (at most " +
             std::to_string(opt_.max_shape_points) + " a shape); file refused";
    return;
  }
  total_points_ += s.points.size();
  if (total_points_ > opt_.max_points) return too_complex(n);
  const double op = st.group_opacity;
  paint_failed_ = false;
  s.role = ctx.role;
  s.owner = ctx.owner;
  if (ctx.role == ShapeRole::Clip) {  // a clip path's shape: its geometry, by clip-rule
    s.fill.enabled = true;
    s.fill.color = Rgba{1, 1, 1, 1};
    s.fill.rule = st.clip_rule;
    s.layer = layer_index(ctx);
    ch_.shapes.push_back(std::move(s));
    return;
  }
  // A gradient fill or stroke: a texture that deforms with the shape (svg_paint.cpp).
  if (s.element != "line") {
    Affine2 uv;
    if (auto tex = gradient_paint(st.fill, n, ctx, s.points, 0.0, uv)) {
      s.fill.enabled = true;
      s.fill.color = Rgba{1, 1, 1, 1};
      s.fill.opacity = static_cast<float>(st.fill_opacity * op);
      s.fill.rule = st.fill_rule;
      s.fill.texture = std::move(tex);
      s.fill.uv_from_point = uv;
    }
  }
  // A pattern fill: its tiles as shapes of a layer clipped by this shape (svg_paint.cpp).
  bool patterned = false;
  if (!s.fill.enabled && s.element != "line" && st.fill.kind == Paint::Url && ctx.role == ShapeRole::Paint)
    if (pugi::xml_node server = lookup_iri(st.fill.url); server && local_name(server) == "pattern")
      patterned = pattern_fill(server, n, ctx, s);
  if (!s.fill.enabled && !patterned) {
    if (auto c = resolve(st.fill, n, st); c && s.element != "line") {  // (lines never fill; other open
      s.fill.enabled = true;                                             // sub-paths fill as if closed)
      s.fill.color = *c;
      s.fill.opacity = static_cast<float>(st.fill_opacity * op);
      s.fill.rule = st.fill_rule;
    }
  }
  if (st.stroke_width > 0) {
    // The width scales by the geometric mean of the transform's scales; when it scales x and
    // y apart (or skews), the pen keeps the rest as its shape (Stroke::pen). A non-scaling
    // stroke keeps its width in the document's units, with a round pen.
    const double scale = std::sqrt(std::abs(ctx.ctm.det()));
    const double width = st.stroke_width * (st.non_scaling ? 1.0 : scale);
    const Affine2& m = ctx.ctm;
    const bool similar = std::abs(m.a - m.d) + std::abs(m.b + m.c) <= 1e-9 * scale ||  // turn and scale
                         std::abs(m.a + m.d) + std::abs(m.b - m.c) <= 1e-9 * scale;   // mirrored
    if (!st.non_scaling && !similar && scale > 0 && std::isfinite(scale))
      s.stroke.pen = Affine2{m.a / scale, m.b / scale, m.c / scale, m.d / scale, 0, 0};
    Affine2 uv;
    if (auto tex = gradient_paint(st.stroke, n, ctx, s.points, 0.5 * width, uv)) {
      s.stroke.enabled = true;
      s.stroke.color = Rgba{1, 1, 1, 1};
      s.stroke.texture = std::move(tex);
      s.stroke.uv_from_point = uv;
    } else if (auto c = resolve(st.stroke, n, st)) {
      s.stroke.enabled = true;
      s.stroke.color = *c;
    }
    if (s.stroke.enabled) {
      s.stroke.opacity = static_cast<float>(st.stroke_opacity * op);
      s.stroke.width = width;
      s.stroke.join = st.join;
      s.stroke.cap = st.cap;
      s.stroke.miter_limit = st.miter_limit;
      s.stroke.under_fill = st.stroke_first;
      dash(n, st, scale, s);
    }
  }
  if (!s.fill.enabled && !s.stroke.enabled) {
    if (patterned) return;
    if (paint_failed_) {  // (its warning, naming it, was given where the paint was resolved)
      count(ch_.dropped, "its paint could not be resolved");
    }
    return;
  }
  if (s.fill.enabled && s.fill.opacity * s.fill.color.a <= 0 &&
      (!s.stroke.enabled || s.stroke.opacity * s.stroke.color.a <= 0)) {
    return;  // fully transparent
  }
  if (s.fill.enabled) close_for_fill(s);
  s.layer = layer_index(ctx);
  ch_.shapes.push_back(std::move(s));
}

// A filled open sub-path is filled as if closed: it is an outline like any other (a part to
// the rig, a region to the solvers), only its stroke keeps its ends. (A sub-path with no area,
// a straight line, stays a line.)
void SvgLoader::close_for_fill(SubShape& s) {
  if (std::none_of(s.contours.begin(), s.contours.end(), [](const Contour& c) { return !c.closed && c.count >= 3; })) return;
  Points out;
  out.reserve(s.points.size());
  for (Contour& c : s.contours) {
    const auto from = s.points.begin() + c.begin;
    Points pts(from, from + c.count);
    c.begin = int(out.size());
    if (!c.closed && pts.size() >= 3) {
      Vec2 lo = pts[0], hi = pts[0];
      for (const Vec2& p : pts) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
      const double extent = (hi - lo).norm();
      if (std::abs(signed_area(pts)) > 1e-4 * extent * extent) {
        // (drawn back to where it began without a z: its last point is its first, and its
        // stroke goes round with a join there instead of two caps)
        const bool back = (pts.back() - pts.front()).norm() <= 1e-9 * extent;
        if (back) pts.pop_back();
        c.closed = true;
        c.open_stroke = !back;
      }
    }
    c.count = int(pts.size());
    out.insert(out.end(), pts.begin(), pts.end());
  }
  s.points = std::move(out);
}

// stroke-dasharray onto the shape's stroke, in character units. A pattern that would cut the
// outline into more than 20,000 dashes is drawn solid, with a warning (a bound on the work a
// frame does for one file).
void SvgLoader::dash(const pugi::xml_node& n, const Style& st, double scale, SubShape& s) {
  if (st.dashes.empty() || !(scale > 0)) return;
  double period = 0, length = 0;
  for (double d : st.dashes) period += d * scale;
  for (const Contour& c : s.contours)
    for (int k = 1; k < c.count + (c.closed ? 1 : 0); ++k)
      length += (s.points[size_t(c.begin + k % c.count)] - s.points[size_t(c.begin + k - 1)]).norm();
  if (!(period > 0) || !std::isfinite(length)) return;
  if (length / period * double(st.dashes.size()) > 20000) {
    warn(n, "stroke-dasharray cuts the outline into more than 20000 dashes; drawn solid");
    count(ch_.approximated, "dashes drawn solid (too many)");
    return;
  }
  for (double d : st.dashes) s.stroke.dashes.push_back(d * scale);
  s.stroke.dash_offset = st.dash_offset * scale;
}

int SvgLoader::layer_index(const Ctx& ctx) {
  auto [it, fresh] = layer_ids_.try_emplace(ctx.layer_key, static_cast<int>(ch_.layers.size()));
  if (fresh) ch_.layers.push_back(ctx.layer_name);
  return it->second;
}

void SvgLoader::make_ids_unique() {
  std::map<std::string, int> seen;
  for (SubShape& s : ch_.shapes) {
    const int k = ++seen[s.id];
    if (k > 1) {
      s.id.push_back('.');
      s.id.append(std::to_string(k));
    }
  }
}

void SvgLoader::svg_image(const pugi::xml_node& n, const Ctx& ctx, const std::vector<unsigned char>& bytes, const std::string& label) {
  if (nested_depth_ >= 3) {
    warn(n, "SVG images nest more than 3 deep; this one skipped");
    return;
  }
  if (bytes.size() >= 2 && bytes[0] == 0x1f && bytes[1] == 0x8b) {
    warn(n, "a compressed SVG (.svgz) as an image is not supported; skipped");
    return;
  }
  auto nd = std::make_unique<NestedDoc>();
  nd->text.assign(bytes.begin(), bytes.end());
  const pugi::xml_parse_result pr = nd->doc.load_buffer(nd->text.data(), nd->text.size(),
                                                        pugi::parse_default | pugi::parse_ws_pcdata_single, pugi::encoding_auto);
  pugi::xml_node root = pr ? nd->doc.document_element() : pugi::xml_node();
  if (root) resolve_namespaces(root);
  if (!root || local_name(root) != "svg") {
    warn(n, label + (pr ? " is not an SVG document" : std::string(" is malformed XML: ") + pr.description()) + "; skipped");
    return;
  }
  // Its own document while it is read: its name and lines (what a warning names), its ids and
  // its style sheets; nothing of the drawing's reaches into it.
  std::string name = label;
  std::string_view text = nd->text;
  std::vector<size_t> lines{0};
  for (size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n') lines.push_back(i + 1);
  std::unordered_map<std::string, pugi::xml_node> ids;
  css::Sheet sheet;
  std::swap(name_, name);
  std::swap(text_, text);
  std::swap(line_starts_, lines);
  std::swap(ids_, ids);
  std::swap(sheet_, sheet);
  ++nested_depth_;
  index_ids(root);
  collect_style_sheets(root);
  // Its size: its width and height, else its viewBox's (the image's box where it gives none).
  const auto vb = svg::parse_viewbox(root.attribute("viewBox").value());
  const Viewport outer{vb ? (*vb)[2] : 100.0, vb ? (*vb)[3] : 100.0};
  double iw = length_attr(root, "width", 0, outer, outer.w), ih = length_attr(root, "height", 1, outer, outer.h);
  if (!(iw > 0)) iw = outer.w;
  if (!(ih > 0)) ih = outer.h;
  double w = 0, h = 0;
  image_size(n, ctx.vp, iw, ih, w, h);
  if (w > 0 && h > 0 && std::isfinite(w) && std::isfinite(h)) {
    Ctx c = ctx;
    c.style = compute_style(root, Style{});  // (an image inherits no style)
    c.depth = ctx.depth + 1;
    const std::array<double, 4> box = vb ? *vb : std::array<double, 4>{0, 0, iw, ih};
    const char* par = n.attribute("preserveAspectRatio") ? n.attribute("preserveAspectRatio").value() : nullptr;
    if (visible_element(root)) visit_nested_svg(n, c, root, w, h, false, &box, par);
  }
  --nested_depth_;
  std::swap(name_, name);
  std::swap(text_, text);
  std::swap(line_starts_, lines);
  std::swap(ids_, ids);
  std::swap(sheet_, sheet);
}

// <text>: its characters in runs (each the text of one element, in its style), laid out along
// the baseline from x, y (and dx, dy) in chunks (a chunk starts where an x or y is given, and
// stands from its x by its text-anchor), each run then drawn as one shape of glyph outlines in
// its element's fill and stroke. The first of a list of x, y, dx, dy values is taken.
void SvgLoader::text(const pugi::xml_node& n, const Ctx& ctx) {
  constexpr size_t kMaxChars = 100000;  // characters of text in one document
  struct Run {
    pugi::xml_node node;
    Ctx ctx;
    std::string chars;
    std::optional<double> x, y;
    double dx = 0, dy = 0;
    bool shown = true;
  };
  std::vector<Run> runs;
  Run pending;
  auto first_length = [&](const pugi::xml_node& e, const char* attr, int axis, const Ctx& c) -> std::optional<double> {
    std::string_view v = e.attribute(attr).value();
    while (!v.empty() && (v.front() == ' ' || v.front() == '\t' || v.front() == '\n' || v.front() == '\r')) v.remove_prefix(1);
    v = v.substr(0, v.find_first_of(" ,\t\n\r"));
    if (v.empty()) return std::nullopt;
    auto k = svg::parse_length(v, axis, c.vp.w, c.vp.h, c.style.font_size);
    if (!k || !std::isfinite(*k)) return std::nullopt;
    return k;
  };
  auto position = [&](const pugi::xml_node& e, const Ctx& c) {
    if (auto x = first_length(e, "x", 0, c)) pending.x = x;
    if (auto y = first_length(e, "y", 1, c)) pending.y = y;
    if (auto dx = first_length(e, "dx", 0, c)) pending.dx += *dx;
    if (auto dy = first_length(e, "dy", 1, c)) pending.dy += *dy;
  };
  bool space_before = true;
  std::function<void(const pugi::xml_node&, const Ctx&, bool)> walk = [&](const pugi::xml_node& e, const Ctx& c, bool shown) {
    for (pugi::xml_node k : e.children()) {
      if (!fatal_.empty()) return;
      if (k.type() == pugi::node_pcdata || k.type() == pugi::node_cdata) {
        if (text_chars_ >= kMaxChars) continue;
        std::string chars;
        if (c.style.preserve_space) {
          chars = k.value();
          std::replace_if(chars.begin(), chars.end(), [](char ch) { return ch == '\n' || ch == '\r' || ch == '\t'; }, ' ');
          space_before = !chars.empty() && chars.back() == ' ';
        } else {
          chars = svg::collapse_white_space(k.value(), space_before);
        }
        if (chars.empty()) continue;
        if (text_chars_ + chars.size() > kMaxChars) {
          warn(e, "more than " + std::to_string(kMaxChars) + " characters of text in the document; the rest skipped");
          count(ch_.dropped, "text past the document's characters");
          chars.resize(kMaxChars - text_chars_);
        }
        text_chars_ += chars.size();
        pending.node = e;
        pending.ctx = c;
        pending.chars = std::move(chars);
        pending.shown = shown;
        runs.push_back(std::move(pending));
        pending = Run{};
        continue;
      }
      if (k.type() != pugi::node_element) continue;
      const std::string_view name = local_name(k);
      if (name == "tspan" || name == "a") {
        if (++elements_ > opt_.max_elements) {
          fatal_ = where(k) + ": more than " + std::to_string(opt_.max_elements) + " elements; file refused";
          return;
        }
        if (c.depth > 200) {  // (as visit: the walk recurses once a level)
          warn(k, "nesting deeper than 200 levels; skipped");
          continue;
        }
        if (!passes_conditions(k) || !visible_element(k)) continue;
        Ctx kc = c;
        kc.depth = c.depth + 1;
        current_vp_ = c.vp;
        kc.style = compute_style(k, c.style);
        position(k, kc);
        walk(k, kc, shown && kc.style.visible);
      } else if (name == "textPath" || name == "tref") {
        warn(k, std::string(name) + " is not supported; its text skipped");
        count(ch_.dropped, std::string(name) + " (text along a path, or referenced)");
      }
    }
  };
  position(n, ctx);
  walk(n, ctx, true);
  // (a trailing space is no part of the layout)
  if (!runs.empty() && !runs.back().ctx.style.preserve_space && !runs.back().chars.empty() && runs.back().chars.back() == ' ')
    runs.back().chars.pop_back();
  if (runs.empty()) return;
  if (!shaper_) shaper_ = std::make_unique<svg::TextShaper>();
  // Each run shaped once, its outlines placed along the baseline from the pen; a chunk's runs
  // then moved by its anchor once its width is known, and drawn. (Outlines past what the file's
  // points left can hold are not made: emit refuses the run that goes over, as any shape.)
  std::vector<std::vector<PathCmd>> cmds(runs.size());
  size_t room = points_left();  // (commands: each at least a point)
  Vec2 pen = Vec2::Zero();
  size_t chunk = 0;
  double chunk_x = 0;
  auto finish_chunk = [&](size_t end) {
    if (end <= chunk) return;
    // (its width ends at its last character: letter-spacing goes between characters)
    const int anchor = runs[chunk].ctx.style.text_anchor;
    const double width = pen.x() - chunk_x - runs[end - 1].ctx.style.letter_spacing;
    const double shift = anchor == 1 ? -0.5 * width : anchor == 2 ? -width : 0.0;
    for (size_t i = chunk; i < end && fatal_.empty(); ++i) {
      for (PathCmd& c : cmds[i]) {
        c.c1.x() += shift;
        c.c2.x() += shift;
        c.p.x() += shift;
      }
      if (!cmds[i].empty()) emit(runs[i].node, runs[i].ctx, cmds[i]);
      std::vector<PathCmd>().swap(cmds[i]);  // (its memory too)
    }
    room = points_left();
  };
  std::string problem;
  for (size_t i = 0; i < runs.size() && fatal_.empty(); ++i) {
    Run& r = runs[i];
    if (r.x || r.y) {
      finish_chunk(i);
      chunk = i;
      if (r.x) pen.x() = *r.x;
      if (r.y) pen.y() = *r.y;
      chunk_x = pen.x();
    }
    pen += Vec2(r.dx, r.dy);
    if (i == 0) chunk_x = pen.x();
    const bool drawn = r.shown && r.ctx.style.visible;
    double advance = 0;
    if (!shaper_->shape({r.ctx.style.font_family, r.ctx.style.font_weight, r.ctx.style.italic}, r.ctx.style.font_size, r.chars,
                        r.ctx.style.letter_spacing, pen, drawn ? &cmds[i] : nullptr, std::min(room, opt_.max_shape_points) + 1, advance,
                        problem)) {
      warn(r.node, problem + "; its text skipped");
      count(ch_.dropped, "text with no font");
    } else if (!problem.empty() && !fonts_capped_) {
      warn(r.node, problem);
      count(ch_.approximated, "text in a font not asked for (too many fonts)");
      fonts_capped_ = true;
    }
    room -= std::min(room, cmds[i].size());
    pen.x() += advance;
  }
  finish_chunk(runs.size());
}

}  // namespace mar::svg_load
