// Layers on the software rasterizer (DrawList::layers): a group drawn into a buffer of its own,
// then blurred (three box blurs in each direction, the standard approximation of a Gaussian,
// SVG 1.1 15.17), shifted, clipped by its clip items' coverage, masked by its mask items'
// luminance or alpha, and put over what lies below at its opacity. Work is bounded to each
// layer's pixel box (its triangles' bounds, widened by three standard deviations of blur).
//
// Buffers keep their capacity: after the first frame at a size, drawing allocates nothing.
#pragma once

#include "render/raster.h"

#include <cstdint>
#include <vector>

namespace mar {

class Compositor {
 public:
  /// Draws the whole list onto `target` with `raster`: items outside every layer as the
  /// rasterizer draws them, each layer through its own buffer.
  void draw(Rasterizer& raster, const DrawList& list, const PixelTarget& target);
  /// Makes now the buffers a list with layers nested `depth` deep needs on a w x h target (a
  /// layer that first shows late in a show, such as a character fading in, then allocates nothing).
  void reserve(size_t depth, int w, int h);

 private:
  struct Box {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< half-open, in pixels
    bool empty() const { return x1 <= x0 || y1 <= y0; }
  };
  void range(Rasterizer& raster, const DrawList& list, const PixelTarget& target, int index_begin, int index_end, size_t& layer);
  PixelTarget take(const PixelTarget& like, const Box& box);  ///< a cleared buffer (inside `box`)
  Box bounds(const DrawList& list, int index_begin, int index_end, double pad, const PixelTarget& t) const;
  void blur(const PixelTarget& t, const Box& box, double sigma);
  std::vector<std::vector<std::uint8_t>> pool_;
  size_t used_ = 0;
  std::vector<std::uint32_t> line_;  ///< a row or column being blurred (four channels, summed)
  std::vector<std::uint8_t> copy_;   ///< the same, as read
  std::vector<int> nest_;            ///< the layers a layer is in (draw)
};

}  // namespace mar
