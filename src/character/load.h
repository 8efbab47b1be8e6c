// Loads a character from any supported file: SVG, PNG (+ optional mask), or a folder of PNG
// layers (character/raster_loader.h: load_layers).
#pragma once

#include "character/character.h"

#include <string>

namespace mar {

struct LoadOptions {
  double svg_tolerance = 0.1;    ///< curve flattening tolerance, output units
  std::string mask_path;         ///< PNG characters: mask image (non-black = figure)
  double raster_tolerance = 0.75;
  /// An SVG's <image> may name a file outside the SVG's folder (default: skipped with a warning).
  bool images_anywhere = false;
};

/// Chooses the loader by content (a folder: its PNG layers; a PNG signature; else SVG/XML). Every failure is
/// bad input: a message naming the file and, where known, the line.
Result<Character> load_character(const std::string& path, const LoadOptions& options = {});

}  // namespace mar
