// Turns a character (rest or deformed) into triangles for SDL_RenderGeometry.
#pragma once

#include "character/character.h"

#include <SDL2/SDL_render.h>

#include <array>
#include <span>

namespace mar {

/// Per-shape data computed once per character: fill triangulations of the rest pose
/// (reused for deformed poses through FillMesh's vertex sources) and texture coordinates.
struct ShapeMesh {
  FillMesh fill;
  std::vector<SDL_FPoint> uv;  ///< #fill.vertices texture coordinates (textured fills only)
  /// The fill's outline, for fringe anti-aliasing (DrawList::fringe): each edge that only one
  /// triangle has, as {a, b, c} — the edge a-b and that triangle's third vertex c (the inside).
  std::vector<std::array<int, 3>> outline;
};

struct CharacterMesh {
  std::vector<ShapeMesh> shapes;  ///< one per Character::shapes entry
};

CharacterMesh prepare_mesh(const Character& ch);

/// Triangles in draw order. Consecutive triangles sharing a texture form one batch.
/// Buffers keep their capacity across clear(), so rebuilding a list of the same
/// character every frame stops allocating after the first frames.
struct DrawList {
  struct Batch {
    const Texture* texture = nullptr;
    int first_index = 0;
    int index_count = 0;
  };
  std::vector<SDL_Vertex> vertices;
  std::vector<int> indices;
  std::vector<Batch> batches;
  /// Where each paint item (one shape's fill, one stroke) begins, as offsets into `indices`:
  /// the anti-aliased rasterizer covers an item's triangles together (render/raster.h).
  std::vector<int> item_starts;
  /// Per paint item (parallel to item_starts): its outline, a range of `outline` — index pairs
  /// a, b into `vertices`, each the edge a -> b of one of its triangles that no other triangle
  /// of the item has, in that triangle's winding. Empty for strokes, and for a fill with a
  /// triangle turned over (a fold): the rasterizer then covers the triangles themselves. Its
  /// triangles' inner edges cancel, so the outline alone gives the same coverage, with a third
  /// of the edges (plain lists only).
  std::vector<std::array<int, 2>> item_outline;
  std::vector<int> outline;
  /// Layers (Character::composites), as ranges of `indices`: the content [begin, content_end)
  /// is drawn into a layer of its own (nested layers inside it likewise), the clip items
  /// [content_end, clip_end) into its clip (opaque white: their union), the mask items
  /// [clip_end, mask_end) into its mask; the layer is then blurred (`blur_px`: the standard
  /// deviation), shifted, clipped, masked and put onto what lies below at `opacity`. Listed in
  /// the order they begin (outer first). Items outside every layer are drawn as before.
  struct Layer {
    int begin = 0, content_end = 0, clip_end = 0, mask_end = 0;
    float opacity = 1.0f, blur_px = 0.0f;
    Vec2 offset_px{0, 0};
    bool clipped = false, masked = false, mask_alpha = false;
    bool shadow = false;              ///< blur and offset make a shadow under the layer
    SDL_Color shadow_color{0, 0, 0, 255};  ///< its colour (straight alpha)
    int composite = -1;  ///< which of the character's composites
  };
  std::vector<Layer> layers;
  std::vector<int> layer_stack;  ///< working space (build_draw_list)
  std::vector<std::pair<int, float>> alpha_stack;  ///< working space: opacity groups on the GPU's list (their end, opacity)
  std::vector<Vec2> scratch;  ///< working space
  std::vector<Vec2> dash_scratch;  ///< working space (one dash of a dashed stroke)
  /// Anti-aliased geometry for renderers that only draw aliased triangles (the GPU's): when
  /// set before build_draw_list(), every fill and stroke comes with a fringe, a strip one pixel
  /// wide along its outline whose alpha falls from the item's to 0 (docs/algorithms.md §8, NanoVG's
  /// way). The inside is pulled in by half a pixel, so the fringe straddles the true edge.
  /// Textured fills then carry premultiplied modulation colours (their textures are uploaded
  /// premultiplied, see Canvas). The software rasterizer wants the plain list (fringe unset).
  bool fringe = false;
  struct FringeVertex {
    Vec2 p{0, 0}, off{0, 0};  ///< position; outward offset to the outer edge of the fringe
    double count = 0, f = 1;  ///< outline edges met here; how far it may be pulled in (0..1)
    double j[4] = {0, 0, 0, 0};  ///< d(uv)/d(position), textured fills
    int outer = -1;           ///< the fringe's outer vertex
    int next[2] = {-1, -1};   ///< its neighbours along the outline
  };
  std::vector<FringeVertex> fringe_scratch;  ///< working space

  /// Room for twice what each buffer holds now (a show's warm-up: later poses may need more).
  void reserve_twice() {
    auto twice = [](auto& v) {
      if (v.capacity() < 2 * v.size()) v.reserve(2 * v.size());
    };
    twice(vertices);
    twice(indices);
    twice(batches);
    twice(item_starts);
    twice(item_outline);
    twice(outline);
    twice(scratch);
    twice(dash_scratch);
    twice(fringe_scratch);
    twice(layers);
    twice(layer_stack);
    twice(alpha_stack);
  }

  void clear() {
    layers.clear();
    vertices.clear();
    indices.clear();
    batches.clear();
    item_starts.clear();
    item_outline.clear();
    outline.clear();
  }
};

struct StrokeStyle {
  double half_width = 0.5;
  LineJoin join = LineJoin::Miter;
  LineCap cap = LineCap::Butt;
  double miter_limit = 4;
  double tolerance = 0.25;  ///< max deviation of round joins/caps, same units as points
};

/// Appends the triangles of one stroked polyline (already in pixel space).
void stroke_polyline(std::span<const Vec2> pts, bool closed, const StrokeStyle& style,
                     SDL_Color color, DrawList& out);

/// Appends fill and stroke triangles of every shape, in paint order, mapped by `view`
/// (character units -> pixels). `positions` gives per-shape deformed points (same sizes
/// as the rest points); empty = rest pose. `tolerance_px` bounds round join error. `shown`:
/// per shape, 0 leaves it out (empty = every shape). `opacity` < 1: the whole drawing at that
/// opacity, composited as one (a layer round it; on a list with fringes, the GPU's, multiplied
/// into every shape).
void build_draw_list(const Character& ch, const CharacterMesh& mesh,
                     std::span<const Points> positions, const Affine2& view,
                     double tolerance_px, DrawList& out, std::span<const char> shown = {}, float opacity = 1.0f);

}  // namespace mar
