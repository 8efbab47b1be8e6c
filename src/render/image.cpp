#include "render/image.h"

#include "character/raster_loader.h"
#include "base/read_file.h"

#include <stb/stb_image_write.h>

#include <algorithm>
#include <cstdlib>

namespace mar {

std::string write_png(const std::string& path, const Image& img) {
  if (img.width <= 0 || img.height <= 0) return path + ": empty image";
  // Encoded in memory, then written with every write checked (stb's own file writer ignores a
  // full disk and leaves an empty file).
  std::string png;
  const auto append = [](void* to, void* data, int size) { static_cast<std::string*>(to)->append(static_cast<const char*>(data), size_t(size)); };
  if (!stbi_write_png_to_func(append, &png, img.width, img.height, 4, img.rgba.data(), img.width * 4))
    return path + ": cannot encode PNG";
  return write_file(path, png);
}

Result<Image> read_png_image(const std::string& path) {
  Result<Texture> t = read_png(path);
  if (!t.ok()) return Result<Image>::failure(t.error);
  return Result<Image>::success(Image{t.value->width, t.value->height, std::move(t.value->rgba)});
}

Image downsample_premultiplied(const std::uint8_t* premul, int width, int height, int factor) {
  Image out{width, height, std::vector<std::uint8_t>(static_cast<size_t>(width) * height * 4)};
  const int big_w = width * factor;
  const int n = factor * factor;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      unsigned sum[4] = {0, 0, 0, 0};
      for (int sy = 0; sy < factor; ++sy) {
        const std::uint8_t* row = premul + (static_cast<size_t>(y * factor + sy) * big_w + x * factor) * 4;
        for (int sx = 0; sx < factor; ++sx) {
          for (int c = 0; c < 4; ++c) sum[c] += row[sx * 4 + c];
        }
      }
      std::uint8_t* o = &out.rgba[(static_cast<size_t>(y) * width + x) * 4];
      const unsigned a = (sum[3] + n / 2) / n;
      o[3] = static_cast<std::uint8_t>(a);
      for (int c = 0; c < 3; ++c) {
        // straight = premultiplied / alpha (both averaged over the same samples)
        const unsigned v = sum[3] ? (sum[c] * 255 + sum[3] / 2) / sum[3] : 0;
        o[c] = static_cast<std::uint8_t>(std::min(255u, v));
      }
    }
  }
  return out;
}

ImageDiff compare_images(const Image& a, const Image& b, int tolerance) {
  ImageDiff d;
  d.same_size = a.width == b.width && a.height == b.height;
  if (!d.same_size) return d;
  d.total = static_cast<size_t>(a.width) * a.height;
  for (size_t i = 0; i < d.total; ++i) {
    const std::uint8_t* pa = &a.rgba[i * 4];
    const std::uint8_t* pb = &b.rgba[i * 4];
    int worst = std::abs(pa[3] - pb[3]);
    if (pa[3] != 0 || pb[3] != 0) {
      // compare premultiplied colour so invisible colour noise does not count
      for (int c = 0; c < 3; ++c) {
        const int va = pa[c] * pa[3] / 255, vb = pb[c] * pb[3] / 255;
        worst = std::max(worst, std::abs(va - vb));
      }
    }
    d.max_channel_diff = std::max(d.max_channel_diff, worst);
    if (worst > tolerance) ++d.differing;
  }
  return d;
}

Image flatten_on(const Image& img, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  Image out = img;
  const std::uint8_t bg[3] = {r, g, b};
  for (size_t i = 0; i < out.rgba.size(); i += 4) {
    const unsigned a = out.rgba[i + 3];
    for (int c = 0; c < 3; ++c) {
      out.rgba[i + c] = static_cast<std::uint8_t>((out.rgba[i + c] * a + bg[c] * (255 - a) + 127) / 255);
    }
    out.rgba[i + 3] = 255;
  }
  return out;
}

}  // namespace mar
