// RGBA8 images: PNG input/output, supersampling reduction, comparison.
#pragma once

#include "character/character.h"

#include <cstdint>
#include <string>
#include <vector>

namespace mar {

/// Straight-alpha RGBA8, row-major, 4 * width * height bytes.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;
};

/// Writes a PNG; returns an error message or empty on success.
std::string write_png(const std::string& path, const Image& img);
Result<Image> read_png_image(const std::string& path);

/// Box-filters a premultiplied RGBA8 buffer of (width*factor) x (height*factor) down to
/// width x height and converts it to straight alpha.
Image downsample_premultiplied(const std::uint8_t* premul, int width, int height, int factor);

/// Per-pixel comparison: a pixel differs when any channel differs by more than
/// `tolerance` (0..255). Fully transparent pixels compare equal whatever their colour.
struct ImageDiff {
  bool same_size = false;
  size_t differing = 0;
  size_t total = 0;
  int max_channel_diff = 0;
  double differing_share() const { return total ? static_cast<double>(differing) / total : 1.0; }
};
ImageDiff compare_images(const Image& a, const Image& b, int tolerance);

/// Composites straight-alpha `img` over an opaque background colour.
Image flatten_on(const Image& img, std::uint8_t r, std::uint8_t g, std::uint8_t b);

}  // namespace mar
