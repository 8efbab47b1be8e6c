// The anti-aliased software rasterizer: every pixel gets the exact share of its area a paint
// item covers. Signed area and cover are accumulated per cell along each edge, then one prefix
// sum per row gives the coverage (the font-rs / stb_truetype approach, ALGORITHMS.md §8). A
// paint item is one shape's fill or one stroke: all its triangles go into the accumulation
// together, so the edges they share cancel exactly. There are no seams inside a shape, strokes
// have no pinholes at joins, and a stroke thinner than a pixel covers what it covers.
//
// Colours are composited in premultiplied form onto premultiplied RGBA8 pixels. Textured fills
// (raster characters) sample their image bilinearly at each pixel's centre, through the
// triangle that holds it; edge pixels whose centre is outside take a neighbour's sample.
//
// Buffers grow to the largest target seen and keep their capacity: after the first frame at a
// size, drawing allocates nothing.
#pragma once

#include "render/tessellate.h"

#include <cstdint>
#include <vector>

namespace mar {

/// Premultiplied RGBA8 pixels (bytes R, G, B, A), `stride` bytes a row.
struct PixelTarget {
  std::uint8_t* px = nullptr;
  int width = 0, height = 0, stride = 0;
};

class Rasterizer {
 public:
  /// Draws the list's triangles in order. A paint item starts at each of the list's item
  /// starts, and wherever the colour or the texture changes.
  void draw(const DrawList& list, const PixelTarget& target);

 private:
  void begin(const PixelTarget& t);
  void add_line(float x0, float y0, float x1, float y1);
  void add_triangle(const SDL_FPoint& a, const SDL_FPoint& b, const SDL_FPoint& c);
  void sample_triangle(const SDL_Vertex& a, const SDL_Vertex& b, const SDL_Vertex& c, const Texture& tex);
  void composite_solid(SDL_Color color, const PixelTarget& t);
  void composite_textured(const PixelTarget& t);

  int w_ = 0, h_ = 0, stride_ = 0;  ///< cells: the target's width plus two
  std::vector<float> acc_;           ///< signed area and cover per cell; zero between items
  std::vector<std::uint32_t> color_; ///< textured items: premultiplied sample per pixel
  std::vector<std::uint8_t> has_;    ///< textured items: 1 where color_ holds a sample
  int bx0_ = 0, by0_ = 0, bx1_ = 0, by1_ = 0;  ///< the current item's cells (half-open)
};

}  // namespace mar
