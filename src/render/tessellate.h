// Turns a character (rest or deformed) into triangles for SDL_RenderGeometry.
#pragma once

#include "character/character.h"

#include <SDL2/SDL_render.h>

#include <span>

namespace mar {

/// Per-shape data computed once per character: fill triangulations of the rest pose
/// (reused for deformed poses through FillMesh's vertex sources) and texture coordinates.
struct ShapeMesh {
  FillMesh fill;
  std::vector<SDL_FPoint> uv;  ///< #fill.vertices texture coordinates (textured fills only)
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
  std::vector<Vec2> scratch;  ///< working space

  void clear() {
    vertices.clear();
    indices.clear();
    batches.clear();
    item_starts.clear();
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
/// per shape, 0 leaves it out (empty = every shape).
void build_draw_list(const Character& ch, const CharacterMesh& mesh,
                     std::span<const Points> positions, const Affine2& view,
                     double tolerance_px, DrawList& out, std::span<const char> shown = {});

}  // namespace mar
