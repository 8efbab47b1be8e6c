// Raster characters: a PNG with alpha, or a PNG plus a mask PNG (non-black = figure).
#pragma once

#include "character/character.h"

#include <cstddef>
#include <string>
#include <string_view>

namespace mar {

struct RasterOptions {
  std::string mask_path;    ///< optional mask PNG, same size as the image
  float threshold = 0.5f;   ///< alpha (or mask brightness) above this is figure
  double tolerance = 0.75;  ///< outline simplification, pixels
  double min_area = 8.0;    ///< regions and holes smaller than this (px^2) are dropped
  size_t max_pixels = 16'000'000;  ///< larger images refused from the header (at most kMaxImagePixels)
};

/// Traces the figure outline (marching squares on alpha or mask, sub-pixel), simplifies
/// it, keeps holes, and makes one textured sub-shape per connected region.
Result<Character> load_raster(const std::string& path, const RasterOptions& options = {});

/// Same from an RGBA8 image in memory (mask optional: `mask_rgba` empty = use alpha).
Result<Character> raster_character(std::shared_ptr<const Texture> image,
                                   const std::vector<std::uint8_t>& mask_rgba,
                                   const std::string& name, const RasterOptions& options = {});

/// A folder of PNG layers, one part each: each layer's alpha is traced into a part textured
/// with the layer. Paint order: `layers.toml` in the folder (`order = ["body.png", ...]`,
/// back to front), else the file names' order (`10-body.png`, `20-arm-left.png`: numbers
/// first, so 9 comes before 10). A part is named after its file without the leading number
/// (`arm-left`). Every layer has the first layer's size. A layer that cannot be used (missing,
/// unreadable, too big, another size, nothing opaque) is left out with a warning naming it;
/// a folder with no usable layer is an error.
Result<Character> load_layers(const std::string& folder, const RasterOptions& options = {});
/// At most this many layers in a folder.
constexpr int kMaxLayers = 256;

/// Limits of an image (or mask): at most kMaxImageSide pixels a side and kMaxImagePixels
/// in all (64 MB as RGBA8); a larger one is refused from its header, before decoding.
constexpr int kMaxImageSide = 8192;
constexpr size_t kMaxImagePixels = 16'000'000;

/// Decodes a PNG (or JPEG, GIF, BMP) in memory as RGBA8; an image over `max_pixels` (or the
/// limits above) is refused from its header, before decoding. `name` starts the messages.
Result<Texture> decode_png(std::string_view bytes, const std::string& name, size_t max_pixels = kMaxImagePixels);
/// Reads a PNG as RGBA8 (base/read_file.h, then decode_png).
Result<Texture> read_png(const std::string& path, size_t max_pixels = kMaxImagePixels);

}  // namespace mar
