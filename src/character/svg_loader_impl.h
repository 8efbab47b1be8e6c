// The SVG loader's private parts (character/svg_loader.h is its interface): the style a
// traversal carries and the loader itself, one stage per file —
//   svg_loader.cpp    parsing, bookkeeping, viewports and the traversal (use, nested svg);
//   svg_style.cpp     the cascade: presentation attributes, CSS, paint and visibility;
//   svg_geometry.cpp  shapes to contours, images to textured rectangles, layers and ids.
#pragma once

#include "character/color.h"
#include "character/css.h"
#include "character/svg_loader.h"
#include "character/svg_parse.h"
#include "character/svg_text.h"

#include <pugixml.hpp>

#include <array>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

namespace mar::svg_load {

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
  std::vector<double> dashes;  // stroke-dasharray in user units (even count; empty: solid)
  double dash_offset = 0;
  bool stroke_first = false;   // paint-order puts the stroke under the fill
  bool non_scaling = false;    // vector-effect: non-scaling-stroke (not inherited)
  std::string marker_start, marker_mid, marker_end;  // marker references (url(#id)), inherited
  FillRule clip_rule = FillRule::NonZero;            // (inherited)
  // fill or stroke currentColor: inherited as the keyword, each element's own color (CSS Color 4)
  bool fill_current = false, stroke_current = false;
  double font_size = 16;  // what em and ex lengths are, and text's size (inherited)
  // Text (svg_text.cpp), all inherited: the font asked for, where a chunk of text stands from
  // its x (0 start, 1 middle, 2 end), what is added after each character, xml:space.
  std::string font_family = "Times New Roman";
  int font_weight = 400;
  bool italic = false;
  int text_anchor = 0;
  double letter_spacing = 0;
  bool preserve_space = false;
};

// A gradient's stop: where (0..1, never before the one before it) and its colour with opacity.
struct GradientStop {
  double offset = 0;
  Rgba color{0, 0, 0, 1};
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
  ShapeRole role = ShapeRole::Paint;  // inside a clipPath or mask: what its shapes are for
  int owner = -1;                     // and whose (Character::composites)
};

class SvgLoader {
 public:
  SvgLoader(const std::string& name, const SvgOptions& opt) : name_(name), opt_(opt) {}

  Result<Character> run(std::string_view text);

 private:
  // ---- bookkeeping -------------------------------------------------------------------
  int line_of(size_t offset) const;
  int line_of(const pugi::xml_node& n) const;
  std::string where(const pugi::xml_node& n) const;
  void warn(const pugi::xml_node& n, const std::string& msg);

  // Namespaces as XML defines them: every element's prefix (or the default namespace) is
  // resolved against the xmlns declarations in scope, once, before anything is read.
  void resolve_namespaces(const pugi::xml_node& root);
  // An SVG element's local name ("path" for <path>, <svg:path> or <s:path> with s bound to the
  // SVG namespace); an element of another namespace keeps its whole name, or, unprefixed in a
  // foreign default namespace, gets "foreign:" + its name (visit() skips names with ':').
  std::string_view local_name(const pugi::xml_node& n) const;
  // Its first child element named `local` (by local_name), or none.
  pugi::xml_node child_named(const pugi::xml_node& n, std::string_view local) const;
  void count(std::map<std::string, int>& m, const std::string& reason) { ++m[reason]; }

  void index_ids(const pugi::xml_node& root);

  pugi::xml_node lookup_iri(std::string_view ref) const;

  static const char* href_of(const pugi::xml_node& n);

  // A paint server and what it names by href, while they are of `kinds` (16 at most, no loops);
  // an attribute is the first one set along it: chain_node says which node sets it (or none).
  std::vector<pugi::xml_node> href_chain(const pugi::xml_node& first, std::initializer_list<std::string_view> kinds) const;
  static pugi::xml_node chain_node(const std::vector<pugi::xml_node>& chain, const char* name);
  // The stops of a gradient's chain: those of the first gradient along it that has any.
  std::vector<GradientStop> gradient_stops(const std::vector<pugi::xml_node>& chain, const Rgba& current);

  // ---- properties ------------------------------------------------------------------
  using Decls = std::vector<std::pair<std::string, std::string>>;

  // Cascade: presentation attributes < CSS rules (by specificity, then order) < the style
  // attribute < CSS !important. The last declaration of a property wins in prop().
  Decls declarations(const pugi::xml_node& n) const;

  void collect_style_sheets(const pugi::xml_node& root);

  static std::optional<std::string_view> prop(const Decls& d, std::string_view key);

  std::optional<Paint> parse_paint(std::string_view v, const pugi::xml_node& n);

  double length_attr(const pugi::xml_node& n, const char* attr, int axis, const Viewport& vp,
                     double fallback);

  Style compute_style(const pugi::xml_node& n, const Style& parent);

  // A hidden child of a group of alternatives: an element with display: none whose parent is a
  // group (not a layer) with a child that shows (a hand's poses, one visible). It is kept,
  // hidden until a swap set shows it; other hidden content (a hidden layer, a sketch) is not.
  bool alternative(const pugi::xml_node& n);

  bool visible_element(const pugi::xml_node& n);

  // Representative solid colour for a paint server, with a warning.
  std::optional<Rgba> paint_server_color(const pugi::xml_node& server, const pugi::xml_node& user,
                                         const Style& st);

  // Resolves a paint to a colour (alpha included); nullopt = nothing drawn.
  std::optional<Rgba> resolve(const Paint& p, const pugi::xml_node& user, const Style& st);

  // ---- viewports ---------------------------------------------------------------------
  Affine2 element_transform(const pugi::xml_node& n);
  std::optional<Vec2> transform_origin(const pugi::xml_node& n);
  // `m` about `n`'s transform-origin, if it has one.
  Affine2 about_origin(const pugi::xml_node& n, const Affine2& m) {
    const auto o = transform_origin(n);
    return o ? Affine2::translate(o->x(), o->y()) * m * Affine2::translate(-o->x(), -o->y()) : m;
  }

  // ---- traversal ---------------------------------------------------------------------
  void visit(const pugi::xml_node& n, const Ctx& parent);

  bool passes_conditions(const pugi::xml_node& c);

  // Nested <svg> (or a <symbol>/<svg> instanced by <use>): a new viewport.
  // `viewbox`, `par`: the viewport's, when they are not `content`'s (an SVG image's).
  void visit_nested_svg(const pugi::xml_node& n, Ctx ctx, const pugi::xml_node& content,
                        double use_w, double use_h, bool from_use, const std::array<double, 4>* viewbox = nullptr,
                        const char* par = nullptr);
  // <image> of an SVG document: the document read on its own (its ids, style sheets, lines and
  // name; no style inherited) and drawn as a nested viewport at the image's box, clipped to it.
  void svg_image(const pugi::xml_node& n, const Ctx& ctx, const std::vector<unsigned char>& bytes, const std::string& label);

  void visit_use(const pugi::xml_node& n, Ctx ctx);

  // ---- geometry ----------------------------------------------------------------------
  void shape(const pugi::xml_node& n, const Ctx& ctx);

  // ---- gradients (svg_paint.cpp) -----------------------------------------------------
  // A gradient as a texture over the shape's rest bounds (`points`, character units; a stroke's
  // widened by `pad` each side) and the map from a rest point to its texture coordinates;
  // nullptr when `server` is no gradient with stops, or the shape or gradient is degenerate
  // (the caller falls back to one colour).
  std::shared_ptr<const Texture> gradient_texture(const pugi::xml_node& server, const Ctx& ctx, std::span<const Vec2> points,
                                                  double pad, Affine2& uv);
  // A paint naming a gradient, as a texture (gradient_texture) within the texel budget; nullptr
  // when it names none (or the budget is spent: said).
  std::shared_ptr<const Texture> gradient_paint(const Paint& p, const pugi::xml_node& n, const Ctx& ctx,
                                                std::span<const Vec2> points, double pad, Affine2& uv);
  size_t gradient_texels_ = 0;
  // Layers open around what is being read: at most kMaxLayerDepth nest (each nesting is a
  // canvas-sized buffer when drawn: 190 nested opacity groups took 1.6 GB at 1920x1080); deeper
  // ones are drawn without their layer, said.
  static constexpr int kMaxLayerDepth = 8;
  int layer_depth_ = 0;
  // A pattern fill of shape `s` (being emitted): a composite of the pattern's tiles over the
  // shape's bounds, clipped by the shape; false (nothing added) when it cannot be (no content,
  // a degenerate tile, more than 256 tiles: said), and the caller paints a colour instead.
  bool pattern_fill(const pugi::xml_node& server, const pugi::xml_node& n, const Ctx& ctx, const SubShape& s);  // all gradients' textures so far (SvgOptions::max_gradient_texels)

  // ---- composites (svg_composite.cpp) ------------------------------------------------
  // An element drawn as a layer (Character::composites): opacity on a group (or on a shape with
  // both fill and stroke), a filter with feGaussianBlur/feOffset, a clip-path, a mask. Returns
  // the composite's index (its content is what the element draws next), or -1; takes the
  // element's own opacity out of `ctx` (the layer applies it).
  int begin_composite(const pugi::xml_node& n, const Ctx& parent, Ctx& ctx);
  bool read_filter(const pugi::xml_node& f, const Ctx& ctx, Composite& c);
  // After its content: its clip path's and mask's shapes.
  void end_composite(int index, const pugi::xml_node& n, const Ctx& ctx);
  // The shapes of a clipPath or mask's content, for composite `index`.
  void matte(int index, const pugi::xml_node& server, const Ctx& ctx, ShapeRole role);

  // ---- markers (svg_marker.cpp) ----------------------------------------------------
  // The markers a shape names, drawn at its vertices as shapes of
  // their own after it, oriented and scaled as the marker element says.
  void markers(const pugi::xml_node& n, const Ctx& ctx, const std::vector<PathCmd>& cmds);

  // ---- images ------------------------------------------------------------------------
  void image_size(const pugi::xml_node& n, const Viewport& vp, double iw, double ih, double& w, double& h);

  // <image>: a textured rectangle placed by x, y, width, height and preserveAspectRatio.
  void image(const pugi::xml_node& n, const Ctx& ctx);
  // <text> and its <tspan>s as shapes (svg_geometry.cpp; fonts by svg::TextShaper).
  void text(const pugi::xml_node& n, const Ctx& ctx);

  // The point budget (SvgOptions::max_points): what is left of it, and the error past it.
  size_t points_left() const { return opt_.max_points - std::min(opt_.max_points, total_points_); }
  void too_complex(const pugi::xml_node& n);

  void emit(const pugi::xml_node& n, const Ctx& ctx, const std::vector<PathCmd>& cmds);

  int layer_index(const Ctx& ctx);

  void dash(const pugi::xml_node& n, const Style& st, double scale, SubShape& s);
  static void close_for_fill(SubShape& s);

  void make_ids_unique();

  std::string name_;
  SvgOptions opt_;
  std::string_view text_;
  std::vector<size_t> line_starts_{0};
  pugi::xml_document doc_;
  // Per element (pugixml's node object): the length of its SVG prefix with ':' to skip, or
  // kForeign. An element not in the map (none should be) is read by its name as written.
  static constexpr uint16_t kForeign = 0xFFFF;
  std::unordered_map<const void*, uint16_t> ns_skip_;
  std::string foreign_name_;  // (local_name's answer for an unprefixed foreign element)
  bool paint_failed_ = false;  // the shape being emitted had a paint that could not be resolved
  std::unordered_map<std::string, pugi::xml_node> ids_;
  std::vector<pugi::xml_node> use_stack_;
  std::set<std::string> warned_;
  std::map<int, int> layer_ids_;
  css::Sheet sheet_;
  std::map<std::string, std::shared_ptr<const Texture>> images_;
  struct NestedDoc {  // an SVG image's document, while its nodes are read (nothing keeps them after)
    std::string text;
    pugi::xml_document doc;
  };
  int nested_depth_ = 0;
  Viewport current_vp_;
  double current_font_ = 16;  // the element being read's font-size (em, ex)
  std::unique_ptr<svg::TextShaper> shaper_;  // made at the first text
  size_t text_chars_ = 0;                    // characters laid out so far (bounded)
  bool fonts_capped_ = false;                // said that too many fonts were asked for
  pugi::xml_node css_transform_of_;           // the element compute_style read last, and
  std::optional<std::string> css_transform_;  // its CSS transform property, if it has one
  Character ch_;
  size_t total_points_ = 0;
  size_t elements_ = 0;  // visited so far, each <use> expansion again (SvgOptions::max_elements)
  std::string fatal_;
};

}  // namespace mar::svg_load
