// Composites (svg_loader_impl.h): an element drawn as one layer. `opacity` on a group (or on a
// shape with both fill and stroke, which overlap) composites the group at that opacity instead
// of multiplying it into each child; `filter` blurs it (feGaussianBlur, and feOffset shifting the
// result) or puts a drop shadow under it (read_filter); any other filter is not drawn, said; `clip-path` clips it to the union of the
// clipPath's shapes (clipPathUnits both ways, clip-rule); `mask` multiplies it by the mask's
// luminance (or alpha, mask-type: alpha). Clip and mask shapes are shapes of the character
// (ShapeRole::Clip, ::Mask): they deform with it, so a clip follows the part it clips.
#include "character/svg_loader_impl.h"

#include <cmath>

namespace mar::svg_load {
namespace {

bool container(std::string_view name) { return name == "g" || name == "a" || name == "use" || name == "svg" || name == "switch"; }

// The standard deviation of an feGaussianBlur (one radius: the mean of two).
double std_deviation(const pugi::xml_node& p) {
  const std::vector<std::string_view> sd = svg::split_list(p.attribute("stdDeviation").value(), 2);
  if (sd.empty()) return 0;
  const double sx = svg::parse_number(sd[0]).value_or(0), sy = sd.size() > 1 ? svg::parse_number(sd[1]).value_or(0) : sx;
  return sx > 0 && sy > 0 && std::isfinite(sx * sy) ? std::sqrt(sx * sy) : 0;
}

}  // namespace

// A filter the layer can draw: a chain of feGaussianBlur and feOffset on SourceGraphic (blur,
// shift); or a drop shadow — Inkscape's (feFlood, feComposite in SourceGraphic, feGaussianBlur,
// feOffset, then feComposite or feMerge putting SourceGraphic over it) or the older one
// (feGaussianBlur of SourceAlpha, feOffset, feMerge with SourceGraphic last). False otherwise.
bool SvgLoader::read_filter(const pugi::xml_node& f, const Ctx& ctx, Composite& c) {
  const double scale = std::sqrt(std::abs(ctx.ctm.det()));
  bool flood = false, source_alpha = false, over_source = false, other = false;
  Rgba color{0, 0, 0, 1};
  for (pugi::xml_node p : f.children()) {
    if (p.type() != pugi::node_element) continue;
    const std::string_view k = local_name(p), in = p.attribute("in").value(), in2 = p.attribute("in2").value();
    if (k == "feGaussianBlur") {
      c.blur = std_deviation(p) * scale;
      source_alpha = source_alpha || in == "SourceAlpha";
    } else if (k == "feOffset") {
      const double dx = svg::parse_number(p.attribute("dx").value()).value_or(0), dy = svg::parse_number(p.attribute("dy").value()).value_or(0);
      if (std::isfinite(dx) && std::isfinite(dy)) c.offset = ctx.ctm.apply_linear(Vec2(dx, dy));
    } else if (k == "feFlood") {
      flood = true;
      const Decls d = declarations(p);
      for (const auto& [key, value] : d) {
        if (key == "flood-color")
          if (auto col = parse_color(value)) color = Rgba{col->r, col->g, col->b, color.a * col->a};
        if (key == "flood-opacity") color.a *= static_cast<float>(svg::parse_opacity(value, 1));
      }
      if (auto a = p.attribute("flood-opacity")) color.a = static_cast<float>(svg::parse_opacity(a.value(), 1));
      if (auto a = p.attribute("flood-color"))
        if (auto col = parse_color(a.value())) color = Rgba{col->r, col->g, col->b, color.a};
    } else if (k == "feComposite") {
      const std::string_view op = p.attribute("operator").value();
      if (op == "in" && (in2 == "SourceGraphic" || in2 == "SourceAlpha")) continue;  // (the flood in the shape)
      if ((op.empty() || op == "over") && in == "SourceGraphic") over_source = true;
      else other = true;
    } else if (k == "feMerge") {
      pugi::xml_node last;
      for (pugi::xml_node m : p.children())
        if (m.type() == pugi::node_element && local_name(m) == "feMergeNode") last = m;
      if (last && std::string_view(last.attribute("in").value()) == "SourceGraphic") over_source = true;
      else other = true;
    } else {
      other = true;
    }
  }
  if (other) {
    c.blur = 0;
    c.offset = Vec2::Zero();
    return false;
  }
  if (over_source) {  // a shadow: flood colour (black for SourceAlpha) under the source
    c.shadow = true;
    c.shadow_color = flood ? color : Rgba{0, 0, 0, 1};
  } else if (flood || source_alpha) {
    c.blur = 0;
    c.offset = Vec2::Zero();
    return false;
  }
  return true;
}

int SvgLoader::begin_composite(const pugi::xml_node& n, const Ctx& parent, Ctx& ctx) {
  const Decls d = declarations(n);
  const std::string_view name = local_name(n);
  const Style& st = ctx.style;
  if (ctx.role != ShapeRole::Paint) {  // (inside a clip path or mask: drawn as one matte)
    for (const char* what : {"filter", "clip-path", "mask"})
      if (auto v = prop(d, what); v && trim_space(*v) != "none") {
        warn(n, std::string(what) + " inside a clip path or mask is not drawn; ignored");
        count(ch_.approximated, std::string("a ") + what + " inside a clip path or mask ignored");
      }
    return -1;
  }
  const double folded = ctx.style.group_opacity;  // (the opacity as multiplied into the paints)
  Composite c;
  c.id = *n.attribute("id").value() ? n.attribute("id").value() : std::string(name) + "-L" + std::to_string(line_of(n));
  bool layer = false;
  // Opacity: a container composites as one; so does a shape whose fill and stroke overlap. A
  // shape with one paint keeps it multiplied into that paint (the same pixels, no layer).
  const double own = parent.style.group_opacity > 0 ? st.group_opacity / parent.style.group_opacity : 1.0;
  const bool both = st.fill.kind != Paint::None && st.stroke.kind != Paint::None && st.stroke_width > 0;
  if (own < 0.999 && (container(name) || both)) {
    layer = true;
    c.opacity = static_cast<float>(std::clamp(own, 0.0, 1.0));
    ctx.style.group_opacity = parent.style.group_opacity;
  }
  if (auto v = prop(d, "filter"); v && trim_space(*v) != "none") {
    const pugi::xml_node f = lookup_iri(*v);
    if (!f || local_name(f) != "filter") {
      warn(n, "filter '" + std::string(*v) + "' names no filter; drawn unfiltered");
      count(ch_.approximated, "a filter not found");
    } else {
      if (!read_filter(f, ctx, c)) {
        warn(n, "filter '" + std::string(*v) + "' is more than a blur, an offset or a drop shadow; drawn without it");
        count(ch_.approximated, "a filter drawn without it");
      }
      layer = layer || c.blur > 0 || c.offset.squaredNorm() > 0 || c.shadow;
    }
  }
  for (const char* what : {"clip-path", "mask"}) {
    auto v = prop(d, what);
    if (!v || trim_space(*v) == "none") continue;
    const pugi::xml_node m = lookup_iri(*v);
    const bool clip = what == std::string_view("clip-path");
    if (!m || local_name(m) != (clip ? "clipPath" : "mask")) {
      // (SVG: a reference to nothing is an error and the element is not drawn; browsers draw it)
      warn(n, std::string(what) + " '" + std::string(*v) + "' names no " + (clip ? "clipPath" : "mask") + "; drawn without it");
      count(ch_.approximated, std::string("a ") + what + " not found");
      continue;
    }
    layer = true;
  }
  if (!layer) return -1;
  if (layer_depth_ >= kMaxLayerDepth) {  // (each layer nesting takes a canvas-sized buffer)
    ctx.style.group_opacity = folded;
    warn(n, "layers nested deeper than " + std::to_string(kMaxLayerDepth) + "; drawn without its opacity layer, filter, clip or mask");
    count(ch_.approximated, "layers nested too deep, drawn without them");
    return -1;
  }
  c.first = static_cast<int>(ch_.shapes.size());
  c.end = c.first;
  ch_.composites.push_back(std::move(c));
  return static_cast<int>(ch_.composites.size()) - 1;
}

void SvgLoader::end_composite(int index, const pugi::xml_node& n, const Ctx& ctx) {
  ch_.composites[size_t(index)].end = static_cast<int>(ch_.shapes.size());
  const Decls d = declarations(n);
  for (const char* what : {"clip-path", "mask"}) {
    auto v = prop(d, what);
    if (!v || trim_space(*v) == "none" || ctx.role != ShapeRole::Paint) continue;
    const bool clip = what == std::string_view("clip-path");
    const pugi::xml_node m = lookup_iri(*v);
    if (m && local_name(m) == (clip ? "clipPath" : "mask")) matte(index, m, ctx, clip ? ShapeRole::Clip : ShapeRole::Mask);
  }
}

void SvgLoader::matte(int index, const pugi::xml_node& server, const Ctx& ctx, ShapeRole role) {
  const bool clip = role == ShapeRole::Clip;
  if (std::find(use_stack_.begin(), use_stack_.end(), server) != use_stack_.end() || use_stack_.size() > 32) {
    warn(server, std::string(clip ? "clip path" : "mask") + " used inside itself; skipped");
    return;
  }
  const Composite& comp = ch_.composites[size_t(index)];
  Ctx mc = ctx;
  mc.role = role;
  mc.owner = index;
  mc.depth = ctx.depth + 1;
  mc.hidden = false;
  mc.style = compute_style(server, Style{});
  mc.id_prefix = ctx.id_prefix + comp.id + (clip ? ":clip:" : ":mask:");
  // Units: the element's user space, or its bounding box there (objectBoundingBox).
  const bool bbox = std::string_view(server.attribute(clip ? "clipPathUnits" : "maskContentUnits").value()) == "objectBoundingBox";
  mc.ctm = ctx.ctm;
  if (clip) {
    if (auto t = svg::parse_transform(server.attribute("transform").value()); t && t->is_finite()) mc.ctm = mc.ctm * about_origin(server, *t);
  }
  if (bbox) {
    const Affine2 to_user = ctx.ctm.inverse();
    Bounds b;
    for (int k = comp.first; k < comp.end; ++k)
      if (ch_.shapes[size_t(k)].role == ShapeRole::Paint)
        for (const Vec2& p : ch_.shapes[size_t(k)].points) b.add(to_user.apply(p));
    if (b.empty() || !(b.width() > 0) || !(b.height() > 0)) {
      ch_.composites[size_t(index)].opacity = 0;  // (no box: nothing shows through)
      return;
    }
    // (the clip path's transform, then the box: as resvg has it)
    mc.ctm = mc.ctm * Affine2{b.width(), 0, 0, b.height(), b.lo.x(), b.lo.y()};
  }
  const size_t before = ch_.shapes.size();
  use_stack_.push_back(server);
  for (pugi::xml_node c : server.children()) visit(c, mc);
  use_stack_.pop_back();
  std::vector<int>& into = clip ? ch_.composites[size_t(index)].clip : ch_.composites[size_t(index)].mask;
  for (size_t k = before; k < ch_.shapes.size(); ++k)
    if (ch_.shapes[k].owner == index && ch_.shapes[k].role == role) into.push_back(static_cast<int>(k));
  if (!clip) {
    const Decls d = declarations(server);
    auto type = prop(d, "mask-type");
    ch_.composites[size_t(index)].mask_alpha = type && trim_space(*type) == "alpha";
  }
  // An empty clip path or mask lets nothing through.
  if (into.empty()) ch_.composites[size_t(index)].opacity = 0;
}

}  // namespace mar::svg_load
