// Markers (svg_loader_impl.h): marker-start, marker-mid and marker-end on any shape (SVG 2;
// SVG 1.1 had them on path, line, polyline and polygon only). Each vertex of the path gets its marker's content as shapes of their own,
// drawn after the path: placed by refX/refY, scaled by the stroke width (markerUnits
// strokeWidth) or not (userSpaceOnUse), fitted by viewBox and preserveAspectRatio into
// markerWidth x markerHeight, and turned by orient — a fixed angle, or `auto` (the path's
// direction there, the bisector at a corner; SVG 1.1, 11.6.2) and `auto-start-reverse`.
// The content is not clipped to the marker's box (overflow is taken as visible).
#include "character/svg_loader_impl.h"

#include <cmath>

namespace mar::svg_load {
namespace {

struct Vertex {
  Vec2 p = Vec2::Zero();
  Vec2 in = Vec2::Zero(), out = Vec2::Zero();  // directions of the segments arriving and leaving
};

// A segment's direction at its start and at its end (a cubic's tangents, falling back to its
// other control points where one coincides with its end).
std::pair<Vec2, Vec2> directions(const Vec2& a, const PathCmd& c) {
  if (c.kind != PathCmd::Cubic) return {c.p - a, c.p - a};
  auto first = [](std::initializer_list<Vec2> ds) {
    for (const Vec2& d : ds)
      if (d.squaredNorm() > 1e-24) return d;
    return Vec2(Vec2::Zero());
  };
  return {first({c.c1 - a, c.c2 - a, c.p - a}), first({c.p - c.c2, c.p - c.c1, c.p - a})};
}

std::vector<Vertex> vertices(const std::vector<PathCmd>& cmds) {
  std::vector<Vertex> v;
  Vec2 cur = Vec2::Zero();
  size_t start = 0;
  for (const PathCmd& c : cmds) {
    if (c.kind == PathCmd::Move) {
      start = v.size();
      v.push_back({c.p});
      cur = c.p;
      continue;
    }
    if (v.empty()) v.push_back({cur});
    const auto [d0, d1] = directions(cur, c);
    v.back().out = d0;
    Vertex nv{c.p, d1};
    if (c.kind == PathCmd::Close && start < v.size()) {
      // A closed subpath: its first vertex is a corner between the closing segment and the
      // first one, and so is its last (the same point).
      v[start].in = d1;
      nv.out = v[start].out;
    }
    v.push_back(nv);
    cur = c.p;
  }
  return v;
}

// The angle (degrees) of `auto` orientation at a vertex: the bisector of the directions in and
// out, or the one there is.
double auto_angle(const Vertex& v) {
  const double li = v.in.norm(), lo = v.out.norm();
  Vec2 d = Vec2::Zero();
  if (li > 0 && lo > 0) {
    d = v.in / li + v.out / lo;
    if (d.squaredNorm() < 1e-18) d = v.in;  // a full turn back: the way in
  } else {
    d = li > 0 ? v.in : v.out;
  }
  return d.squaredNorm() > 0 ? std::atan2(d.y(), d.x()) * 180.0 / M_PI : 0.0;
}

}  // namespace

void SvgLoader::markers(const pugi::xml_node& n, const Ctx& ctx, const std::vector<PathCmd>& cmds) {
  const Style& st = ctx.style;
  if (st.marker_start.empty() && st.marker_mid.empty() && st.marker_end.empty()) return;
  const std::vector<Vertex> vs = vertices(cmds);
  if (vs.empty()) return;
  for (size_t i = 0; i < vs.size() && fatal_.empty(); ++i) {
    const std::string& ref = i == 0 ? st.marker_start : i + 1 == vs.size() ? st.marker_end : st.marker_mid;
    if (ref.empty() || ref == "none") continue;
    const pugi::xml_node m = lookup_iri(ref);
    if (!m || local_name(m) != "marker") {
      if (i == 0 || i + 1 == vs.size()) warn(n, "marker '" + ref + "' is no marker; skipped");
      continue;
    }
    if (std::find(use_stack_.begin(), use_stack_.end(), m) != use_stack_.end() || use_stack_.size() > 32) {
      warn(n, "a marker drawn inside itself; skipped");
      continue;
    }
    const Viewport& vp = ctx.vp;
    const double mw = length_attr(m, "markerWidth", 0, vp, 3), mh = length_attr(m, "markerHeight", 1, vp, 3);
    if (!(mw > 0) || !(mh > 0)) continue;  // (a zero-sized marker shows nothing)
    const bool user_units = std::string_view(m.attribute("markerUnits").value()) == "userSpaceOnUse";
    const double scale = user_units ? 1.0 : st.stroke_width;
    if (!(scale > 0)) continue;
    Affine2 fit;
    Viewport inner{mw, mh};
    if (auto vb = svg::parse_viewbox(m.attribute("viewBox").value())) {
      if (!((*vb)[2] > 0) || !((*vb)[3] > 0)) continue;
      fit = svg::viewbox_transform(*vb, mw, mh, m.attribute("preserveAspectRatio").value());
      inner = {(*vb)[2], (*vb)[3]};
    }
    const Vec2 at_ref = fit.apply({length_attr(m, "refX", 0, inner, 0), length_attr(m, "refY", 1, inner, 0)});
    double angle = 0;
    const std::string_view orient = trim_space(m.attribute("orient").value());
    if (orient == "auto" || orient == "auto-start-reverse") {
      angle = auto_angle(vs[i]) + (i == 0 && orient == "auto-start-reverse" ? 180.0 : 0.0);
    } else if (!orient.empty()) {
      std::string_view num = orient;
      double unit = 1;  // degrees, or rad / grad / turn
      for (const auto& [suffix, k] : {std::pair<std::string_view, double>{"deg", 1.0}, {"grad", 0.9}, {"rad", 180.0 / M_PI}, {"turn", 360.0}})
        if (num.size() > suffix.size() && num.substr(num.size() - suffix.size()) == suffix) {
          num.remove_suffix(suffix.size());
          unit = k;
          break;
        }
      angle = svg::parse_number(num).value_or(0) * unit;
    }
    Ctx mc = ctx;
    mc.ctm = ctx.ctm * Affine2::translate(vs[i].p.x(), vs[i].p.y()) * Affine2::rotate(angle) * Affine2::scale(scale, scale) *
             Affine2::translate(-at_ref.x(), -at_ref.y()) * fit;
    if (!std::isfinite(mc.ctm.det())) continue;
    // The content inherits from the marker, not from the path it marks.
    mc.style = compute_style(m, Style{});
    mc.style.group_opacity = st.group_opacity;
    mc.vp = inner;
    mc.depth = ctx.depth + 1;
    const char* id = n.attribute("id").value();
    mc.id_prefix = ctx.id_prefix + (*id ? std::string(id) : "marker-L" + std::to_string(line_of(n))) + ":";
    use_stack_.push_back(m);
    for (pugi::xml_node c : m.children()) visit(c, mc);
    use_stack_.pop_back();
  }
}

}  // namespace mar::svg_load
