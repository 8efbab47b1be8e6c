#include "render/raster.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace mar {
namespace {

// Pixels are bytes R, G, B, A; a packed pixel (pack()) is stored as one 32-bit word.
static_assert(std::endian::native == std::endian::little, "packed RGBA stores assume a little-endian machine");

// x / 255, rounded, for x in 0..255 * 255.
inline std::uint32_t div255(std::uint32_t x) {
  x += 128;
  return (x + (x >> 8)) >> 8;
}

inline std::uint32_t pack(std::uint32_t r, std::uint32_t g, std::uint32_t b, std::uint32_t a) {
  return r | g << 8 | b << 16 | a << 24;
}

// Premultiplied source `s` (packed) at `cov` (0..255) over the premultiplied pixel `d`.
inline void over(std::uint8_t* d, std::uint32_t s, std::uint32_t cov) {
  const std::uint32_t sr = div255((s & 0xFF) * cov), sg = div255((s >> 8 & 0xFF) * cov);
  const std::uint32_t sb = div255((s >> 16 & 0xFF) * cov), sa = div255((s >> 24) * cov);
  const std::uint32_t k = 255 - sa;
  d[0] = std::uint8_t(sr + div255(d[0] * k));
  d[1] = std::uint8_t(sg + div255(d[1] * k));
  d[2] = std::uint8_t(sb + div255(d[2] * k));
  d[3] = std::uint8_t(sa + div255(d[3] * k));
}

inline std::uint32_t coverage_byte(float s) {
  const float c = std::min(1.0f, std::fabs(s));
  return std::uint32_t(c * 255.0f + 0.5f);
}

}  // namespace

void Rasterizer::begin(const PixelTarget& t) {
  w_ = t.width;
  h_ = t.height;
  stride_ = t.width + 2;
  const size_t cells = size_t(stride_) * size_t(std::max(0, h_));
  if (acc_.size() < cells) acc_.resize(cells, 0.0f);
  blocks_ = (stride_ + kBlock - 1) / kBlock;
  if (touched_.size() < size_t(blocks_) * size_t(std::max(0, h_))) touched_.resize(size_t(blocks_) * size_t(std::max(0, h_)), 0);
}

// One edge's signed area and cover, row by row, into the cells it crosses. x is clamped into
// [0, width]: what lies left of the target still covers the pixels right of it.
void Rasterizer::add_line(Band& b, float x0, float y0, float x1, float y1) {
  if (y0 == y1 || !(std::isfinite(x0) && std::isfinite(y0) && std::isfinite(x1) && std::isfinite(y1))) return;
  float dir = 1.0f;
  if (y0 > y1) {
    std::swap(x0, x1);
    std::swap(y0, y1);
    dir = -1.0f;
  }
  const float top = float(b.y0), bottom = float(b.y1), w = float(w_);
  if (y1 <= top || y0 >= bottom) return;
  const float dxdy = (x1 - x0) / (y1 - y0);
  float x = x0;
  if (y0 < top) {
    x += (top - y0) * dxdy;
    y0 = top;
  }
  y1 = std::min(y1, bottom);
  const int ys = int(y0), ye = int(std::ceil(y1));
  for (int y = ys; y < ye; ++y) {
    float* row = acc_.data() + size_t(y) * size_t(stride_);
    const float dy = std::min(float(y + 1), y1) - std::max(float(y), y0);
    const float xnext = x + dxdy * dy;
    const float d = dy * dir;
    const float xa = std::clamp(std::min(x, xnext), 0.0f, w), xb = std::clamp(std::max(x, xnext), 0.0f, w);
    const float xa_floor = std::floor(xa), xb_ceil = std::ceil(xb);
    const int xai = int(xa_floor), xbi = int(xb_ceil);
    std::uint8_t* flags = touched_.data() + size_t(y) * size_t(blocks_);
    for (int k = xai >> kBlockShift, ke = std::min(xbi + 1, stride_ - 1) >> kBlockShift; k <= ke; ++k) flags[k] = 1;
    if (xbi <= xai + 1) {  // within one cell: the trapezoid left of the edge's mid point
      const float xmf = 0.5f * (xa + xb) - xa_floor;
      row[xai] += d - d * xmf;
      row[xai + 1] += d * xmf;
    } else {  // across cells: a triangle in the first, a slope through the middle, a corner in the last
      const float s = 1.0f / (xb - xa);
      const float xaf = xa - xa_floor;
      const float a0 = 0.5f * s * (1.0f - xaf) * (1.0f - xaf);
      const float xbf = xb - xb_ceil + 1.0f;
      const float am = 0.5f * s * xbf * xbf;
      row[xai] += d * a0;
      if (xbi == xai + 2) {
        row[xai + 1] += d * (1.0f - a0 - am);
      } else {
        const float a1 = s * (1.5f - xaf);
        row[xai + 1] += d * (a1 - a0);
        for (int xi = xai + 2; xi < xbi - 1; ++xi) row[xi] += d * s;
        const float a2 = a1 + float(xbi - xai - 3) * s;
        row[xbi - 1] += d * (1.0f - a2 - am);
      }
      row[xbi] += d * am;
    }
    x = xnext;
  }
}

void Rasterizer::add_triangle(Band& b, const SDL_FPoint& a, const SDL_FPoint& q0, const SDL_FPoint& r0) {
  const float lo_y = std::min({a.y, q0.y, r0.y}), hi_y = std::max({a.y, q0.y, r0.y});
  if (!(hi_y > float(b.y0)) || !(lo_y < float(b.y1))) return;  // (also NaN)
  // Every triangle counts positively, so shared edges of neighbours cancel and folds add up.
  const float area2 = (q0.x - a.x) * (r0.y - a.y) - (q0.y - a.y) * (r0.x - a.x);
  if (!(area2 != 0.0f)) return;
  const SDL_FPoint& q = area2 > 0 ? q0 : r0;
  const SDL_FPoint& r = area2 > 0 ? r0 : q0;
  add_line(b, a.x, a.y, q.x, q.y);
  add_line(b, q.x, q.y, r.x, r.y);
  add_line(b, r.x, r.y, a.x, a.y);
  const float lo_x = std::min({a.x, q.x, r.x}), hi_x = std::max({a.x, q.x, r.x});
  b.bx0 = std::min(b.bx0, int(std::clamp(std::floor(lo_x), 0.0f, float(w_))));
  b.bx1 = std::max(b.bx1, int(std::clamp(std::ceil(hi_x), 0.0f, float(w_))) + 2);
  b.by0 = std::min(b.by0, int(std::clamp(std::floor(lo_y), float(b.y0), float(b.y1))));
  b.by1 = std::max(b.by1, int(std::clamp(std::ceil(hi_y), float(b.y0), float(b.y1))));
}

// One outline edge, and the item's cells grown to hold it.
void Rasterizer::add_edge(Band& b, const SDL_FPoint& p, const SDL_FPoint& q) {
  const float lo_y = std::min(p.y, q.y), hi_y = std::max(p.y, q.y);
  if (!(hi_y > float(b.y0)) || !(lo_y < float(b.y1))) return;  // (also NaN)
  add_line(b, p.x, p.y, q.x, q.y);
  b.bx0 = std::min(b.bx0, int(std::clamp(std::floor(std::min(p.x, q.x)), 0.0f, float(w_))));
  b.bx1 = std::max(b.bx1, int(std::clamp(std::ceil(std::max(p.x, q.x)), 0.0f, float(w_))) + 2);
  b.by0 = std::min(b.by0, int(std::clamp(std::floor(lo_y), float(b.y0), float(b.y1))));
  b.by1 = std::max(b.by1, int(std::clamp(std::ceil(hi_y), float(b.y0), float(b.y1))));
}

void Rasterizer::composite_solid(Band& b, SDL_Color c) {
  const PixelTarget& t = target_;
  const std::uint32_t a = c.a;
  const std::uint32_t src = pack(div255(c.r * a), div255(c.g * a), div255(c.b * a), a);
  const int bx0 = b.bx0, xend = std::min(b.bx1, stride_), xdraw = std::min(b.bx1, w_);
  auto span = [&](std::uint8_t* d, int lo, int hi, std::uint32_t cov) {  // constant coverage over [lo, hi)
    if (cov == 0 || lo >= hi) return;
    if (cov == 255 && a == 255) {
      auto* p = reinterpret_cast<std::uint32_t*>(d) + lo;
      for (int x = 0; x < hi - lo; ++x) p[x] = src;
    } else {
      for (int x = lo; x < hi; ++x) over(d + size_t(x) * 4, src, cov);
    }
  };
  for (int y = b.by0; y < b.by1; ++y) {
    float* row = acc_.data() + size_t(y) * size_t(stride_);
    std::uint8_t* flags = touched_.data() + size_t(y) * size_t(blocks_);
    std::uint8_t* d = t.px + size_t(y) * size_t(t.stride);
    float s = 0.0f;
    for (int bx = bx0 & ~(kBlock - 1); bx < xend; bx += kBlock) {
      const int lo = std::max(bx, bx0), hi = std::min(bx + kBlock, xend);
      std::uint8_t& f = flags[bx >> kBlockShift];
      if (!f) {  // no edge here: the running coverage throughout
        span(d, lo, std::min(hi, xdraw), coverage_byte(s));
        continue;
      }
      f = 0;
      for (int x = lo; x < hi; ++x) {
        s += row[x];
        row[x] = 0.0f;
        if (x >= xdraw) continue;  // cells right of the target
        const std::uint32_t cov = coverage_byte(s);
        if (cov == 0) continue;
        std::uint8_t* p = d + size_t(x) * 4;
        if (cov == 255 && a == 255) *reinterpret_cast<std::uint32_t*>(p) = src;
        else over(p, src, cov);
      }
    }
  }
}

// Bilinear sample of a straight-alpha image at texel coordinates (u, v) (centres at +0.5),
// premultiplied and modulated by `mod` (the vertex colour), packed.
namespace {
std::uint32_t sample(const Texture& tex, float u, float v, SDL_Color mod) {
  const float fx = u - 0.5f, fy = v - 0.5f;
  const float x0f = std::floor(fx), y0f = std::floor(fy);
  const float tx = fx - x0f, ty = fy - y0f;
  const int x0 = int(x0f), y0 = int(y0f);
  float acc[4] = {0, 0, 0, 0};
  for (int k = 0; k < 4; ++k) {
    const int x = std::clamp(x0 + (k & 1), 0, tex.width - 1), y = std::clamp(y0 + (k >> 1), 0, tex.height - 1);
    const float wgt = ((k & 1) ? tx : 1 - tx) * ((k >> 1) ? ty : 1 - ty);
    const std::uint8_t* p = tex.rgba.data() + (size_t(y) * size_t(tex.width) + size_t(x)) * 4;
    const float a = p[3] * wgt;
    acc[0] += p[0] * a;
    acc[1] += p[1] * a;
    acc[2] += p[2] * a;
    acc[3] += a;
  }
  const float ma = mod.a / 255.0f;
  const float r = acc[0] / 255.0f * (mod.r / 255.0f) * ma, g = acc[1] / 255.0f * (mod.g / 255.0f) * ma;
  const float b = acc[2] / 255.0f * (mod.b / 255.0f) * ma, al = acc[3] * ma;
  auto byte = [](float f) { return std::uint32_t(std::clamp(f + 0.5f, 0.0f, 255.0f)); };
  return pack(byte(r), byte(g), byte(b), byte(al));
}
}  // namespace

// A textured triangle's samples at the pixel centres inside it.
void Rasterizer::sample_triangle(Band& bd, const SDL_Vertex& a, const SDL_Vertex& b, const SDL_Vertex& c, const Texture& tex) {
  if (tex.width <= 0 || tex.height <= 0) return;
  const float x0 = a.position.x, y0 = a.position.y;
  const float e1x = b.position.x - x0, e1y = b.position.y - y0, e2x = c.position.x - x0, e2y = c.position.y - y0;
  const float det = e1x * e2y - e1y * e2x;
  if (!(std::fabs(det) > 1e-12f) || !std::isfinite(det)) return;  // (degenerate, or a vertex at infinity)
  const float inv = 1.0f / det;
  // The band's rows and one more each side (edge pixels there take a neighbour's sample);
  // bounds clamped as floats first (a far-flung vertex must not overflow an int).
  auto pixel_lo = [](float v, float lo, float hi) { return int(std::clamp(std::ceil(v - 0.5f), lo, hi)); };
  auto pixel_hi = [](float v, float lo, float hi) { return int(std::clamp(std::floor(v - 0.5f), lo, hi)); };
  const float ytop = float(std::max(0, bd.y0 - 1)), ybottom = float(std::min(h_ - 1, bd.y1)), xright = float(w_ - 1);
  const int ylo = pixel_lo(std::min({a.position.y, b.position.y, c.position.y}), ytop, ybottom + 1);
  const int yhi = pixel_hi(std::max({a.position.y, b.position.y, c.position.y}), ytop - 1, ybottom);
  const int xlo = pixel_lo(std::min({a.position.x, b.position.x, c.position.x}), 0, xright + 1);
  const int xhi = pixel_hi(std::max({a.position.x, b.position.x, c.position.x}), -1, xright);
  const float tw = float(tex.width), th = float(tex.height);
  // Each barycentric coordinate is linear along a row: l = A px + B. Where each is at least 0
  // bounds the row's span, so only the pixels of the span are visited (a sliver across the
  // shape costs its area, not its bounding box).
  const float a1 = e2y * inv, a2 = -e1y * inv, a0 = -(a1 + a2);
  for (int y = ylo; y <= yhi; ++y) {
    const float py = float(y) + 0.5f - y0;
    const float b1 = -py * e2x * inv, b2 = e1x * py * inv, b0 = 1 - (b1 + b2);
    float lo = -1e30f, hi = 1e30f;
    for (const auto& [ak, bk] : {std::pair{a0, b0}, std::pair{a1, b1}, std::pair{a2, b2}}) {
      if (ak > 0) lo = std::max(lo, (-1e-6f - bk) / ak);
      else if (ak < 0) hi = std::min(hi, (-1e-6f - bk) / ak);
      else if (bk < -1e-6f) hi = -1e30f;
    }
    if (!(hi >= lo)) continue;
    const int sx0 = std::max(xlo, int(std::clamp(std::floor(lo + x0 - 0.5f), -1.0f, xright + 1)));
    const int sx1 = std::min(xhi, int(std::clamp(std::ceil(hi + x0 - 0.5f), -1.0f, xright + 1)));
    for (int x = sx0; x <= sx1; ++x) {
      const float px = float(x) + 0.5f - x0;
      const float l1 = (px * e2y - py * e2x) * inv, l2 = (e1x * py - e1y * px) * inv;
      if (l1 < -1e-6f || l2 < -1e-6f || l1 + l2 > 1 + 1e-6f) continue;
      const float l0 = 1 - l1 - l2;
      const float u = l0 * a.tex_coord.x + l1 * b.tex_coord.x + l2 * c.tex_coord.x;
      const float v = l0 * a.tex_coord.y + l1 * b.tex_coord.y + l2 * c.tex_coord.y;
      const size_t i = size_t(y - (bd.y0 - 1)) * size_t(w_) + size_t(x);
      bd.color[i] = sample(tex, u * tw, v * th, a.color);
      bd.has[i] = 1;
    }
  }
}

void Rasterizer::composite_textured(Band& b) {
  const PixelTarget& t = target_;
  const int xend = std::min(b.bx1, stride_), xdraw = std::min(b.bx1, w_);
  const int first = b.y0 - 1;  // the sample buffers' first row
  for (int y = b.by0; y < b.by1; ++y) {
    float* row = acc_.data() + size_t(y) * size_t(stride_);
    std::uint8_t* d = t.px + size_t(y) * size_t(t.stride);
    float s = 0.0f;
    for (int x = b.bx0; x < xdraw; ++x) {
      s += row[x];
      row[x] = 0.0f;
      const std::uint32_t cov = coverage_byte(s);
      if (cov == 0) continue;
      size_t i = size_t(y - first) * size_t(w_) + size_t(x);
      if (!b.has[i]) {  // an edge pixel whose centre no triangle holds: a neighbour's sample
        bool found = false;
        for (int dy = -1; dy <= 1 && !found; ++dy)
          for (int dx = -1; dx <= 1 && !found; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if (nx < 0 || ny < 0 || nx >= w_ || ny >= h_) continue;
            const size_t j = size_t(ny - first) * size_t(w_) + size_t(nx);
            if (b.has[j]) {
              i = j;
              found = true;
            }
          }
        if (!found) continue;
      }
      over(d + size_t(x) * 4, b.color[i], cov);
    }
    for (int x = std::max(b.bx0, xdraw); x < xend; ++x) row[x] = 0.0f;
    std::uint8_t* flags = touched_.data() + size_t(y) * size_t(blocks_);
    std::fill(flags + (b.bx0 >> kBlockShift), flags + ((xend - 1) >> kBlockShift) + 1, 0);
  }
  // The samples go with the item (with the rows either side).
  for (int y = std::max(0, b.y0 - 1); y < std::min(h_, b.y1 + 1); ++y) {
    auto row = b.has.begin() + long(y - first) * w_;
    std::fill(row + std::max(0, b.bx0 - 1), row + std::min(w_, b.bx1 + 1), 0);
  }
}

// One band: every paint item, in order, clipped to the band's rows.
void Rasterizer::band(Band& b) {
  const DrawList& list = *list_;
  const auto& v = list.vertices;
  const auto& idx = list.indices;
  size_t next_start = 0;  // into list.item_starts
  for (const DrawList::Batch& batch : list.batches) {
    const Texture* tex = batch.texture;
    const int end = std::min(batch.first_index + batch.index_count, index_end_);
    int k = std::max(batch.first_index, index_begin_);
    while (k + 2 < end) {
      // One paint item: from k to the next item start, colour change or batch end.
      while (next_start < list.item_starts.size() && list.item_starts[next_start] <= k) ++next_start;
      const int stop = next_start < list.item_starts.size() ? std::min(end, list.item_starts[next_start]) : end;
      const SDL_Color col = v[size_t(idx[size_t(k)])].color;
      b.bx0 = w_ + 2;
      b.by0 = b.y1;
      b.bx1 = 0;
      b.by1 = b.y0;
      // A fill with its outline (DrawList::item_outline): the outline's edges stand for the
      // triangles' (the textured ones still sample through the triangles).
      const size_t item = next_start - 1;
      if (next_start > 0 && item < list.item_outline.size() && list.item_starts[item] == k &&
          list.item_outline[item][1] > list.item_outline[item][0]) {
        const auto [o0, o1] = list.item_outline[item];
        for (int e = o0; e + 1 < o1; e += 2) add_edge(b, v[size_t(list.outline[size_t(e)])].position, v[size_t(list.outline[size_t(e + 1)])].position);
        if (tex)
          for (; k + 2 < stop; k += 3) sample_triangle(b, v[size_t(idx[size_t(k)])], v[size_t(idx[size_t(k + 1)])], v[size_t(idx[size_t(k + 2)])], *tex);
        k = stop;
      }
      for (; k + 2 < stop; k += 3) {
        const SDL_Vertex& p = v[size_t(idx[size_t(k)])];
        const SDL_Vertex& q = v[size_t(idx[size_t(k + 1)])];
        const SDL_Vertex& r = v[size_t(idx[size_t(k + 2)])];
        const SDL_Color pc = p.color;
        if (!tex && (pc.r != col.r || pc.g != col.g || pc.b != col.b || pc.a != col.a)) break;
        add_triangle(b, p.position, q.position, r.position);
        if (tex) sample_triangle(b, p, q, r, *tex);
      }
      if (k + 2 >= stop) k = stop;  // (a trailing partial triangle is skipped)
      if (b.by1 <= b.by0 || b.bx1 <= b.bx0) continue;
      if (tex) composite_textured(b);
      else composite_solid(b, col);
    }
  }
}

void Rasterizer::run(Band& b) {
  for (int i; (i = next_band_.fetch_add(1, std::memory_order_relaxed)) < bands_;) {
    b.y0 = i * kChunk;
    b.y1 = std::min(h_, b.y0 + kChunk);
    band(b);
  }
}

void Rasterizer::worker() {
  std::uint32_t seen = 0;
  for (;;) {
    go_.wait(seen, std::memory_order_acquire);
    seen = go_.load(std::memory_order_acquire);
    if (quit_.load()) return;
    run(helper_);
    done_.fetch_add(1, std::memory_order_release);
    done_.notify_one();
  }
}

Rasterizer::~Rasterizer() {
  if (!worker_.joinable()) return;
  quit_ = true;
  go_.fetch_add(1, std::memory_order_release);
  go_.notify_one();
  worker_.join();
}

void Rasterizer::draw(const DrawList& list, const PixelTarget& t) { draw(list, t, 0, static_cast<int>(list.indices.size())); }

void Rasterizer::draw(const DrawList& list, const PixelTarget& t, int index_begin, int index_end) {
  if (!t.px || t.width <= 0 || t.height <= 0 || index_end <= index_begin) return;
  begin(t);
  index_begin_ = index_begin;
  index_end_ = index_end;
  list_ = &list;
  target_ = t;
  bands_ = (h_ + kChunk - 1) / kChunk;
  bool textured = false;
  for (const DrawList::Batch& b : list.batches) textured = textured || b.texture;
  const size_t samples = size_t(kChunk + 2) * size_t(w_);
  for (Band* b : {&own_, &helper_})
    if (textured && b->color.size() < samples) {
      b->color.resize(samples);
      b->has.resize(samples, 0);
    }
  next_band_.store(0, std::memory_order_relaxed);
  const bool two = threads_ == 2 && bands_ >= 4;
  if (two && !worker_.joinable()) worker_ = std::thread([this] { worker(); });
  if (!two) {
    run(own_);
    return;
  }
  const std::uint32_t before = done_.load(std::memory_order_acquire);
  go_.fetch_add(1, std::memory_order_release);  // the helper takes bands too
  go_.notify_one();
  run(own_);
  for (std::uint32_t d; (d = done_.load(std::memory_order_acquire)) == before;) done_.wait(d, std::memory_order_acquire);
}

}  // namespace mar
