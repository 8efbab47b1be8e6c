// Pure parsers for SVG micro-syntaxes: numbers, path data, transform lists, point lists.
#pragma once

#include "character/character.h"
#include "geom/flatten.h"
#include "geom/types.h"

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mar::svg {

/// Reads one SVG number at s[pos] (after optional whitespace/comma separators when
/// `skip_separators`), following the SVG grammar: sign? (digits ('.' digits?)? | '.' digits)
/// exponent?. Compact forms such as ".5.5" and "1e-3-2" are split correctly.
std::optional<double> read_number(std::string_view s, size_t& pos);

/// Skips whitespace and at most one comma.
void skip_separators(std::string_view s, size_t& pos);

/// A path reduced to absolute move/line/cubic/close commands (quadratics are
/// degree-elevated exactly, arcs become cubics of at most 45 degrees).
struct PathCmd {
  enum Kind { Move, Line, Cubic, Close } kind = Move;
  Vec2 c1 = Vec2::Zero(), c2 = Vec2::Zero();  ///< cubic control points
  Vec2 p = Vec2::Zero();                      ///< end point

  /// Move, Line or Close to `to` (control points zero).
  static PathCmd to(Kind k, const Vec2& to) {
    PathCmd c;
    c.kind = k;
    c.p = to;
    return c;
  }
};

struct PathData {
  std::vector<PathCmd> cmds;
  std::string error;       ///< empty when the whole string parsed
  size_t error_pos = 0;    ///< byte offset of the first bad character
  bool too_long = false;   ///< more commands than allowed (nothing kept)
};

/// Parses `d` (M L H V C S Q T A Z, absolute and relative, implicit repeats). On error,
/// keeps everything before the bad command, as SVG's error handling asks. More than
/// `max_commands` commands is an error (each draws at least one point).
PathData parse_path(std::string_view d, size_t max_commands = 4'000'000);

/// Parses a transform list (matrix, translate, scale, rotate with optional centre,
/// skewX, skewY; whitespace and/or commas). Returns nullopt when malformed.
std::optional<Affine2> parse_transform(std::string_view s);

/// Parses a points list for polyline/polygon; an odd trailing number is dropped.
std::vector<Vec2> parse_points(std::string_view s, bool* odd = nullptr);

/// The items of a list separated by whitespace and/or commas (stroke-dasharray, stdDeviation,
/// transform-origin), at most `max_items` of them.
std::vector<std::string_view> split_list(std::string_view s, size_t max_items = SIZE_MAX);

/// A whole attribute value as one finite number (surrounding whitespace allowed).
std::optional<double> parse_number(std::string_view v);

/// Opacity: a number or percentage, clamped to [0, 1]; `fallback` when malformed.
double parse_opacity(std::string_view v, double fallback);

/// A length in px: number with px, pt, pc, mm, cm, in, em (16 px), ex (8 px) or %.
/// Percentages refer to the viewport: axis 0 = width, 1 = height, 2 = the normalised
/// diagonal sqrt((w^2 + h^2) / 2). nullopt when malformed or not finite.
/// `font_size`: what em is (ex: half of it), the element's font-size.
std::optional<double> parse_length(std::string_view v, int axis, double vp_w, double vp_h, double font_size = 16);

/// A `systemLanguage` list ("en, fr-CA") passes when it names English (en or en-*), the
/// language marionette's messages are in.
bool system_language_matches(std::string_view list);

/// Parses a viewBox "min-x min-y width height"; nullopt when malformed or not positive.
std::optional<std::array<double, 4>> parse_viewbox(std::string_view v);

/// The viewBox -> viewport map for a viewport of w x h and a preserveAspectRatio value
/// ("none", or xMin|xMid|xMax + YMin|YMid|YMax, then meet|slice; default xMidYMid meet).
Affine2 viewbox_transform(const std::array<double, 4>& vb, double w, double h, std::string_view par);

/// Outline of a rect with corner radii (already resolved: >= 0, clamped to half the size).
std::vector<PathCmd> rect_path(double x, double y, double w, double h, double rx, double ry);

/// Outline of an ellipse (four quarter arcs).
std::vector<PathCmd> ellipse_path(double cx, double cy, double rx, double ry);

/// Decodes base64 (standard and URL alphabets; whitespace and padding ignored).
std::vector<unsigned char> base64_decode(std::string_view in);

/// The bytes an <image> href names: a base64 data URI, or a file relative to `base_dir`, read as
/// every outside file is (base/read_file.h). A file outside `base_dir` and its subfolders (after
/// following links) is refused unless `anywhere`. `label` names them (the file, or "embedded
/// image"). false with `problem` set when it cannot (remote, outside the folder, missing, not a
/// file, too large). Defined in svg_image.cpp, as the two below.
bool image_href_bytes(std::string_view href, const std::string& base_dir, bool anywhere, std::vector<unsigned char>& bytes,
                      std::string& label, std::string& problem);
/// Whether an href names an SVG document (a data URI of image/svg+xml, a .svg file, or bytes
/// that begin, after any XML prolog, with an <svg element).
bool is_svg_image(std::string_view href, const std::vector<unsigned char>& bytes);
/// Decodes a raster image's bytes (PNG, JPEG, GIF, BMP via stb_image), its size checked from its
/// header first. nullptr with `problem` set when it cannot (too large, undecodable).
std::shared_ptr<const Texture> decode_image_bytes(const std::vector<unsigned char>& bytes, const std::string& label,
                                                  std::string& problem);

/// One flattened contour in output units.
struct FlatContour {
  Points points;
  bool closed = false;
};

/// Transforms path commands by `m` and flattens curves so no point deviates more than
/// `tolerance` (output units) from the curve. Sub-paths with a single point are dropped.
/// Past `max_points` points it stops and sets `*over` (nothing is returned then).
std::vector<FlatContour> flatten_path(const std::vector<PathCmd>& cmds, const Affine2& m, double tolerance,
                                      size_t max_points = SIZE_MAX, bool* over = nullptr);

}  // namespace mar::svg
