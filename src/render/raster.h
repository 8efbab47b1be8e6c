// The anti-aliased software rasterizer: every pixel gets the exact share of its area a paint
// item covers. Signed area and cover are accumulated per cell along each edge, then one prefix
// sum per row gives the coverage (the font-rs / stb_truetype approach, docs/algorithms.md §8). A
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

#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

namespace mar {

/// Premultiplied RGBA8 pixels (bytes R, G, B, A), `stride` bytes a row.
struct PixelTarget {
  std::uint8_t* px = nullptr;
  int width = 0, height = 0, stride = 0;
};

class Rasterizer {
 public:
  Rasterizer() = default;
  ~Rasterizer();
  Rasterizer(const Rasterizer&) = delete;
  Rasterizer& operator=(const Rasterizer&) = delete;

  /// Draws the list's triangles in order. A paint item starts at each of the list's item
  /// starts, and wherever the colour or the texture changes.
  void draw(const DrawList& list, const PixelTarget& target);
  /// The same for the triangles of indices [index_begin, index_end) only (a layer's content,
  /// clip or mask: DrawList::layers), which begin and end at item starts.
  void draw(const DrawList& list, const PixelTarget& target, int index_begin, int index_end);
  /// 1 or 2 threads (default: 2 where the machine has two cores). The target is cut into bands
  /// of kChunk rows that both threads take in turn; each band is drawn whole (every item, in
  /// order) by one thread, so the pixels do not depend on which thread drew them.
  void set_threads(int n) { threads_ = n < 2 ? 1 : 2; }
  static constexpr int kChunk = 64;

 private:
  /// One thread's working state for the band it is drawing.
  struct Band {
    int y0 = 0, y1 = 0;                    ///< the band's rows
    int bx0 = 0, by0 = 0, bx1 = 0, by1 = 0;  ///< the current item's cells there (half-open)
    std::vector<std::uint32_t> color;      ///< textured items: premultiplied samples, rows y0-1 .. y1
    std::vector<std::uint8_t> has;         ///< 1 where color holds a sample
  };
  void begin(const PixelTarget& t);
  void run(Band& b);  ///< takes bands until none is left
  void band(Band& b);
  void add_line(Band& b, float x0, float y0, float x1, float y1);
  void add_triangle(Band& b, const SDL_FPoint& p, const SDL_FPoint& q, const SDL_FPoint& r);
  void add_edge(Band& b, const SDL_FPoint& p, const SDL_FPoint& q);
  void sample_triangle(Band& b, const SDL_Vertex& p, const SDL_Vertex& q, const SDL_Vertex& r, const Texture& tex);
  void composite_solid(Band& b, SDL_Color color);
  void composite_textured(Band& b);
  void worker();

  int w_ = 0, h_ = 0, stride_ = 0;  ///< cells: the target's width plus two
  std::vector<float> acc_;           ///< signed area and cover per cell; zero between items
  /// Per row, a flag per block of kBlock cells that an edge wrote: the sweep runs through the
  /// others at once (their coverage is the running sum's: nothing there, or a span inside).
  static constexpr int kBlockShift = 4, kBlock = 1 << kBlockShift;
  int blocks_ = 0;                   ///< blocks a row
  std::vector<std::uint8_t> touched_;
  // The frame being drawn, and the bands handed out.
  const DrawList* list_ = nullptr;
  PixelTarget target_;
  int index_begin_ = 0, index_end_ = 0;  ///< the range of indices being drawn
  std::atomic<int> next_band_{0};
  int bands_ = 0;
  Band own_, helper_;
  // The second thread: started at the first draw that can use it; woken per frame (no lock).
  int threads_ = std::thread::hardware_concurrency() >= 2 ? 2 : 1;
  std::thread worker_;
  std::atomic<std::uint32_t> go_{0}, done_{0};
  std::atomic<bool> quit_{false};
};

}  // namespace mar
