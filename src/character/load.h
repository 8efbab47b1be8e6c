// Loads a character from any supported file: SVG, PNG (+ optional mask), or a folder of PNG
// layers (character/raster_loader.h: load_layers).
#pragma once

#include "character/character.h"

#include <functional>
#include <string>

namespace mar {

struct LoadOptions {
  double svg_tolerance = 0.1;    ///< curve flattening tolerance, document units (or canvas px, below)
  std::string mask_path;         ///< PNG characters: mask image (non-black = figure)
  double raster_tolerance = 0.75;
  /// An SVG's <image> may name a file outside the SVG's folder (default: skipped with a warning).
  bool images_anywhere = false;
  /// The canvas an SVG character is drawn on: given the document's size, how many canvas pixels
  /// a document unit covers there. Where that is more than 1 (a small drawing shown large),
  /// curves are flattened to within svg_tolerance *pixels* of the true curve instead of units
  /// (at most 64 times finer; the file is read twice). Unset: units.
  std::function<double(double width, double height)> pixels_per_unit;
};

/// Chooses the loader by content (a folder: its PNG layers; a PNG signature; else SVG/XML). Every failure is
/// bad input: a message naming the file and, where known, the line.
Result<Character> load_character(const std::string& path, const LoadOptions& options = {});

}  // namespace mar
