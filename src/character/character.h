// Multi-element 2D character: ordered sub-shapes, never merged into one outline.
#pragma once

#include "geom/triangulate.h"
#include "base/result.h"
#include "geom/types.h"

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace mar {

/// Straight (non-premultiplied) colour, components in [0, 1].
struct Rgba {
  float r = 0, g = 0, b = 0, a = 1;
  bool operator==(const Rgba&) const = default;
};

enum class LineJoin { Miter, Round, Bevel };
enum class LineCap { Butt, Round, Square };

/// RGBA8 image (straight alpha), row-major.
struct Texture {
  std::string name;
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;  ///< 4 * width * height
};

struct Fill {
  bool enabled = false;
  Rgba color;            ///< colour (its alpha comes from the colour value itself)
  float opacity = 1.0f;  ///< fill-opacity times inherited group/element opacity
  FillRule rule = FillRule::NonZero;
  std::shared_ptr<const Texture> texture;  ///< when set, the fill samples this image
  Affine2 uv_from_point;                   ///< rest point -> texture coordinates in [0, 1]
};

struct Stroke {
  bool enabled = false;
  Rgba color;
  float opacity = 1.0f;  ///< stroke-opacity times inherited opacity
  double width = 1.0;    ///< in character units
  LineJoin join = LineJoin::Miter;
  LineCap cap = LineCap::Butt;
  double miter_limit = 4.0;
  /// When set, the stroke samples this image (a gradient): a point's texture coordinates are
  /// uv_from_point of where it lies at rest (a deformed stroke maps back through the affine map
  /// that best fits its shape's deformation).
  std::shared_ptr<const Texture> texture;
  Affine2 uv_from_point;
  /// Dashes (stroke-dasharray: on, off, on, off ... in character units along the rest outline;
  /// a dash stretches as its stretch of outline does), and where the pattern starts.
  std::vector<double> dashes;
  double dash_offset = 0;
  /// Drawn under the shape's fill (paint-order: stroke).
  bool under_fill = false;
  /// The pen's shape (its linear part only): the element's transform scaled to unit area when it
  /// scales x and y apart or skews, so a stroke is drawn as SVG draws it, in the element's own
  /// units (wider one way than the other); identity otherwise.
  Affine2 pen;
  bool round_pen() const { return pen.a == 1 && pen.b == 0 && pen.c == 0 && pen.d == 1; }
};

/// A polyline inside SubShape::points: points[begin .. begin+count).
struct Contour {
  int begin = 0;
  int count = 0;
  bool closed = false;
  /// Closed for its fill only: SVG fills an open sub-path as if closed, so it is an outline
  /// (a part to the rig and the solvers), while its stroke keeps its two ends.
  bool open_stroke = false;
  bool stroke_closed() const { return closed && !open_stroke; }
};

/// What a shape is for: drawn (the default), or the outline of a composite's clip path, or the
/// content of its mask — drawn only into that composite's clip or mask. All deform alike.
enum class ShapeRole { Paint, Clip, Mask };

/// One element of the character: one or more contours (sub-paths, or outline + holes)
/// sharing one style. Points are in character units (document px after viewBox).
struct SubShape {
  std::string id;       ///< id from the file (made unique), or "<tag>-L<line>"
  std::string label;    ///< the name an editor shows (Inkscape's inkscape:label), if any
  /// The groups it is in, outermost first, each by its label (else id), joined by '/'
  /// ("head/Mouth"); empty outside any group. `group_key` tells apart two groups of one name
  /// (-1: none).
  std::string group;
  int group_key = -1;
  /// Its innermost group is a layer (an Inkscape layer, or a <g> at the top of the file): an
  /// artist's sheet of many parts, not one.
  bool group_is_layer = false;
  /// An alternative the file hides (display: none inside a group with a visible child): drawn
  /// only when a swap set or trigger shows it; it deforms with the rest.
  bool hidden = false;
  std::string element;  ///< source element name (path, rect, ..., or "region")
  int line = 0;         ///< source line, 0 if not from a text file
  int layer = 0;        ///< index into Character::layers
  Points points;
  std::vector<Contour> contours;
  Fill fill;
  Stroke stroke;
  ShapeRole role = ShapeRole::Paint;
  int owner = -1;  ///< a clip or mask shape's composite (Character::composites)

  /// True when every contour is closed (one-point contours, interior points a solver
  /// added, do not count).
  bool closed() const;
  /// Inside by the even-odd rule over the closed contours (an outline and its holes).
  bool contains(const Vec2& q) const { return contains(q, points); }
  /// The same with the shape's points at `at` instead (a posed shape: one per point).
  bool contains(const Vec2& q, std::span<const Vec2> at) const;
  /// Its largest closed contour (the outer outline); empty when none is closed.
  Points largest_ring() const;
  Bounds bounds() const;
  std::vector<Ring> rings() const;
};

/// A group drawn as one layer, then put onto what lies below it (SVG: `opacity` on a group,
/// `filter` with feGaussianBlur, `clip-path`, `mask`): its shapes are drawn into a layer of
/// their own, which is blurred and shifted, clipped by the union of its clip shapes, masked by
/// its mask shapes, and composited at its opacity. Composites nest (listed outer first).
struct Composite {
  int first = 0, end = 0;     ///< its shapes, [first, end) in paint order (nested composites' too)
  float opacity = 1.0f;
  double blur = 0;            ///< the Gaussian blur's standard deviation, character units (0: none)
  Vec2 offset{0, 0};          ///< shift of the blurred layer (feOffset), character units
  /// A drop shadow (Inkscape's filter, or a blur of SourceAlpha merged under SourceGraphic):
  /// the blur and offset make a shadow of this colour from the layer's alpha, drawn under it.
  bool shadow = false;
  Rgba shadow_color{0, 0, 0, 1};
  std::vector<int> clip;      ///< its clip shapes (ShapeRole::Clip), whose union clips; empty: none
  std::vector<int> mask;      ///< its mask shapes (ShapeRole::Mask); empty: none
  bool mask_alpha = false;    ///< the mask's alpha (mask-type: alpha), else its luminance
  std::string id;             ///< the element's id, or "<tag>-L<line>"
};

struct Character {
  std::string source;                 ///< file it came from
  double width = 0, height = 0;       ///< document size in character units
  std::vector<std::string> layers;    ///< layer names, in paint order
  std::vector<SubShape> shapes;       ///< in paint order (document order)
  std::vector<Composite> composites;  ///< groups drawn as layers (outer first)
  std::vector<std::string> warnings;  ///< what was approximated or skipped
  /// Shapes not drawn at all, and things drawn approximately, counted by reason (`inspect`).
  std::map<std::string, int> dropped, approximated;

  Bounds bounds() const;
  size_t vertex_count() const;
};

}  // namespace mar
