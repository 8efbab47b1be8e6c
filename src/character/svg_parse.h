// Pure parsers for SVG micro-syntaxes: numbers, path data, transform lists, point lists.
#pragma once

#include "geom/flatten.h"
#include "geom/types.h"

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
};

/// Parses `d` (M L H V C S Q T A Z, absolute and relative, implicit repeats). On error,
/// keeps everything before the bad command, as SVG's error handling asks.
PathData parse_path(std::string_view d);

/// Parses a transform list (matrix, translate, scale, rotate with optional centre,
/// skewX, skewY; whitespace and/or commas). Returns nullopt when malformed.
std::optional<Affine2> parse_transform(std::string_view s);

/// Parses a points list for polyline/polygon; an odd trailing number is dropped.
std::vector<Vec2> parse_points(std::string_view s, bool* odd = nullptr);

/// One flattened contour in output units.
struct FlatContour {
  Points points;
  bool closed = false;
};

/// Transforms path commands by `m` and flattens curves so no point deviates more than
/// `tolerance` (output units) from the curve. Sub-paths with a single point are dropped.
std::vector<FlatContour> flatten_path(const std::vector<PathCmd>& cmds, const Affine2& m,
                                      double tolerance);

}  // namespace mar::svg
