// Raster characters: a PNG with alpha, or a PNG plus a mask PNG (non-black = figure).
#pragma once

#include "character/character.h"

#include <cstddef>
#include <string>

namespace mar {

struct RasterOptions {
  std::string mask_path;    ///< optional mask PNG, same size as the image
  float threshold = 0.5f;   ///< alpha (or mask brightness) above this is figure
  double tolerance = 0.75;  ///< outline simplification, pixels
  double min_area = 8.0;    ///< regions and holes smaller than this (px^2) are dropped
};

/// Traces the figure outline (marching squares on alpha or mask, sub-pixel), simplifies
/// it, keeps holes, and makes one textured sub-shape per connected region.
Result<Character> load_raster(const std::string& path, const RasterOptions& options = {});

/// Same from an RGBA8 image in memory (mask optional: `mask_rgba` empty = use alpha).
Result<Character> raster_character(std::shared_ptr<const Texture> image,
                                   const std::vector<std::uint8_t>& mask_rgba,
                                   const std::string& name, const RasterOptions& options = {});

/// Limits of an image (or mask): at most kMaxImageSide pixels a side and kMaxImagePixels
/// in all (64 MB as RGBA8); a larger one is refused from its header, before decoding.
constexpr int kMaxImageSide = 8192;
constexpr size_t kMaxImagePixels = 16'000'000;

/// Reads a PNG as RGBA8.
Result<Texture> read_png(const std::string& path);

}  // namespace mar
