#include "render/composite.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace mar {

Compositor::Box Compositor::bounds(const DrawList& list, int index_begin, int index_end, double pad, const PixelTarget& t) const {
  float x0 = 1e30f, y0 = 1e30f, x1 = -1e30f, y1 = -1e30f;
  for (int k = index_begin; k < index_end; ++k) {
    const SDL_FPoint& p = list.vertices[size_t(list.indices[size_t(k)])].position;
    x0 = std::min(x0, p.x);
    y0 = std::min(y0, p.y);
    x1 = std::max(x1, p.x);
    y1 = std::max(y1, p.y);
  }
  Box b;
  if (!(x1 >= x0)) return b;
  auto clampi = [](double v, int hi) { return int(std::clamp(v, 0.0, double(hi))); };
  b.x0 = clampi(std::floor(x0 - pad) - 1, t.width);
  b.y0 = clampi(std::floor(y0 - pad) - 1, t.height);
  b.x1 = clampi(std::ceil(x1 + pad) + 1, t.width);
  b.y1 = clampi(std::ceil(y1 + pad) + 1, t.height);
  return b;
}

PixelTarget Compositor::take(const PixelTarget& like, const Box& box) {
  if (used_ == pool_.size()) pool_.emplace_back();  // (draw() made them: not reached)
  std::vector<std::uint8_t>& px = pool_[used_++];
  const size_t stride = size_t(like.width) * 4;
  if (px.size() < stride * size_t(like.height)) px.resize(stride * size_t(like.height));
  for (int y = box.y0; y < box.y1; ++y) std::memset(px.data() + size_t(y) * stride + size_t(box.x0) * 4, 0, size_t(box.x1 - box.x0) * 4);
  return {px.data(), like.width, like.height, int(stride)};
}

// Three box blurs each way; the box width from the standard deviation as SVG 1.1 (15.17) gives
// it, centred (an even width is taken one wider).
void Compositor::blur(const PixelTarget& t, const Box& box, double sigma) {
  if (!(sigma > 0.2) || box.empty()) return;
  const int d = std::max(1, int(std::floor(sigma * 3.0 * std::sqrt(2.0 * M_PI) / 4.0 + 0.5)));
  const int r = d / 2;
  if (r < 1) return;
  const int w = box.x1 - box.x0, h = box.y1 - box.y0;
  const int longest = std::max(w, h);
  if (copy_.size() < size_t(longest) * 4) copy_.resize(size_t(longest) * 4);
  auto pass = [&](std::uint8_t* first, int n, int step) {  // one line of n pixels, `step` bytes apart
    for (int i = 0; i < n; ++i) std::memcpy(&copy_[size_t(i) * 4], first + size_t(i) * size_t(step), 4);
    for (int rep = 0; rep < 3; ++rep) {
      std::uint32_t sum[4] = {0, 0, 0, 0};
      const std::uint32_t win = std::uint32_t(2 * r + 1);
      // (reading copy_, writing the line; then the line back into copy_ for the next pass)
      for (int i = 0; i < std::min(r, n); ++i)
        for (int c = 0; c < 4; ++c) sum[c] += copy_[size_t(i) * 4 + size_t(c)];
      for (int i = 0; i < n; ++i) {
        if (i + r < n)
          for (int c = 0; c < 4; ++c) sum[c] += copy_[size_t(i + r) * 4 + size_t(c)];
        std::uint8_t* o = first + size_t(i) * size_t(step);
        for (int c = 0; c < 4; ++c) o[c] = std::uint8_t((sum[c] + win / 2) / win);
        if (i - r >= 0)
          for (int c = 0; c < 4; ++c) sum[c] -= copy_[size_t(i - r) * 4 + size_t(c)];
      }
      for (int i = 0; i < n; ++i) std::memcpy(&copy_[size_t(i) * 4], first + size_t(i) * size_t(step), 4);
    }
  };
  for (int y = box.y0; y < box.y1; ++y) pass(t.px + size_t(y) * size_t(t.stride) + size_t(box.x0) * 4, w, 4);
  for (int x = box.x0; x < box.x1; ++x) pass(t.px + size_t(box.y0) * size_t(t.stride) + size_t(x) * 4, h, t.stride);
}

void Compositor::range(Rasterizer& raster, const DrawList& list, const PixelTarget& target, int index_begin, int index_end,
                       size_t& layer) {
  int at = index_begin;
  while (layer < list.layers.size() && list.layers[layer].begin < index_end) {
    const DrawList::Layer& l = list.layers[layer++];
    if (l.begin < at) continue;  // (none: layers nest)
    raster.draw(list, target, at, l.begin);
    at = l.mask_end;
    const double pad = 3.0 * l.blur_px + 2;
    Box box = bounds(list, l.begin, l.content_end, pad, target);  // (the shift is applied when put)
    // Shifted, the layer lands elsewhere: it is drawn where it is, put where it goes.
    const int dx = int(std::lround(l.offset_px.x())), dy = int(std::lround(l.offset_px.y()));
    const size_t mark = used_;
    const PixelTarget buf = take(target, box);
    range(raster, list, buf, l.begin, l.content_end, layer);
    if (box.empty() || !(l.opacity > 0)) {
      used_ = mark;
      continue;
    }
    // The filter's result: the layer blurred and shifted, or a shadow of its alpha (blurred,
    // shifted, in the shadow's colour) with the layer over it.
    PixelTarget src = buf;
    int sx = dx, sy = dy;
    if (l.shadow) {
      const Box u{std::max(0, std::min(box.x0, box.x0 + dx)), std::max(0, std::min(box.y0, box.y0 + dy)),
                  std::min(target.width, std::max(box.x1, box.x1 + dx)), std::min(target.height, std::max(box.y1, box.y1 + dy))};
      src = take(target, u);
      const SDL_Color c = l.shadow_color;
      for (int y = std::max(box.y0, -dy); y < std::min(box.y1, target.height - dy); ++y)
        for (int x = std::max(box.x0, -dx); x < std::min(box.x1, target.width - dx); ++x) {
          const std::uint32_t a = buf.px[size_t(y) * size_t(buf.stride) + size_t(x) * 4 + 3] * std::uint32_t(c.a);  // 0..255*255
          std::uint8_t* o = src.px + size_t(y + dy) * size_t(src.stride) + size_t(x + dx) * 4;
          o[0] = std::uint8_t((c.r * a + 32512) / 65025);
          o[1] = std::uint8_t((c.g * a + 32512) / 65025);
          o[2] = std::uint8_t((c.b * a + 32512) / 65025);
          o[3] = std::uint8_t((a + 127) / 255);
        }
      blur(src, u, l.blur_px);
      for (int y = box.y0; y < box.y1; ++y)
        for (int x = box.x0; x < box.x1; ++x) {
          const std::uint8_t* p = buf.px + size_t(y) * size_t(buf.stride) + size_t(x) * 4;
          std::uint8_t* o = src.px + size_t(y) * size_t(src.stride) + size_t(x) * 4;
          const std::uint32_t inv = 255u - p[3];
          for (int i = 0; i < 4; ++i) o[i] = std::uint8_t(std::min<std::uint32_t>(255, p[i] + (o[i] * inv + 127) / 255));
        }
      box = u;
      sx = sy = 0;
    } else {
      blur(buf, box, l.blur_px);
    }
    const Box to{std::max(0, box.x0 + sx), std::max(0, box.y0 + sy), std::min(target.width, box.x1 + sx), std::min(target.height, box.y1 + sy)};
    PixelTarget clip{}, mask{};
    if (l.clipped) {
      clip = take(target, to);
      raster.draw(list, clip, l.content_end, l.clip_end);
    }
    if (l.masked) {
      mask = take(target, to);
      raster.draw(list, mask, l.clip_end, l.mask_end);
    }
    const std::uint32_t op = std::uint32_t(std::lround(std::clamp(l.opacity, 0.0f, 1.0f) * 255.0f));
    for (int y = to.y0; y < to.y1; ++y) {
      const std::uint8_t* s = src.px + size_t(y - sy) * size_t(src.stride);
      std::uint8_t* d = target.px + size_t(y) * size_t(target.stride);
      for (int x = to.x0; x < to.x1; ++x) {
        const std::uint8_t* sp = s + size_t(x - sx) * 4;
        if (sp[3] == 0) continue;
        // The layer's weight here, 0..255*255: opacity, clip coverage, mask.
        std::uint32_t k = op * 255;
        if (clip.px) k = k * clip.px[size_t(y) * size_t(clip.stride) + size_t(x) * 4 + 3] / 255;
        if (mask.px) {
          const std::uint8_t* m = mask.px + size_t(y) * size_t(mask.stride) + size_t(x) * 4;
          // (premultiplied: the luminance of the colour times its alpha; sRGB weights, as resvg)
          const std::uint32_t lum = l.mask_alpha ? m[3] : (2125u * m[0] + 7154u * m[1] + 721u * m[2] + 5000u) / 10000u;
          k = k * std::min<std::uint32_t>(lum, 255) / 255;
        }
        if (k == 0) continue;
        std::uint32_t c[4];
        for (int i = 0; i < 4; ++i) c[i] = (sp[i] * k + 32512) / 65025;
        const std::uint32_t inv = 255 - c[3];
        for (int i = 0; i < 4; ++i) d[x * 4 + i] = std::uint8_t(std::min<std::uint32_t>(255, c[i] + (d[x * 4 + i] * inv + 127) / 255));
      }
    }
    used_ = mark;
  }
  raster.draw(list, target, at, index_end);
}

void Compositor::reserve(size_t depth, int w, int h) {
  const size_t need = depth + 3;
  if (pool_.size() < need) pool_.resize(need);
  for (size_t k = 0; k < need; ++k)
    if (pool_[k].size() < size_t(w) * size_t(h) * 4) pool_[k].resize(size_t(w) * size_t(h) * 4);
  nest_.reserve(depth + 1);
}

void Compositor::draw(Rasterizer& raster, const DrawList& list, const PixelTarget& target) {
  used_ = 0;
  // Every buffer this list can hold at once, made now: a layer's own for each layer it is in,
  // and a shadow, a clip and a mask for the deepest (so a layer that first shows late in a show
  // does not allocate then).
  size_t depth = 0;
  nest_.clear();
  for (const DrawList::Layer& l : list.layers) {
    while (!nest_.empty() && nest_.back() <= l.begin) nest_.pop_back();
    nest_.push_back(l.mask_end);
    depth = std::max(depth, nest_.size());
  }
  const size_t need = list.layers.empty() ? 0 : depth + 3;
  if (pool_.size() < need) pool_.resize(need);
  for (size_t k = 0; k < need; ++k)
    if (pool_[k].size() < size_t(target.width) * size_t(target.height) * 4) pool_[k].resize(size_t(target.width) * size_t(target.height) * 4);
  size_t layer = 0;
  range(raster, list, target, 0, static_cast<int>(list.indices.size()), layer);
}

}  // namespace mar
