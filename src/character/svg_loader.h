// SVG loader for drawings made in Inkscape or Illustrator. XML through pugixml.
#pragma once

#include "character/character.h"

#include <string>
#include <string_view>

namespace mar {

struct SvgOptions {
  /// Curves are flattened so no point is farther than this from the true curve,
  /// in output units (document px after the root viewBox).
  double tolerance = 0.1;
  /// Upper bound on the total number of points; a larger file is rejected as bad input
  /// (flattening stops there, so memory stays bounded too).
  size_t max_points = 4'000'000;
  /// Upper bound on the elements visited, each <use> expansion counted again: a few <use>
  /// nested ten deep make 10^9 elements out of 2 KB, so bytes and points do not bound the time.
  /// Past it the file is refused (about 0.5 s of loading on a 2-core PC).
  size_t max_elements = 200'000;
  /// Upper bound on one shape's points after flattening: its fill is triangulated, so one huge
  /// shape is refused rather than tied up for minutes (the whole file's budget is max_points).
  size_t max_shape_points = 100'000;
  /// Gradient fills are drawn from textures made at load (up to 256 x 256 each); past this many
  /// texels in all (64 MB), further gradients are drawn as their mean colour, with a warning.
  size_t max_gradient_texels = 16'000'000;
  /// Upper bound on the file's size in bytes (64 MB).
  size_t max_bytes = size_t(64) << 20;
  /// An <image> may name a file outside the SVG's own folder (and below it); by default such an
  /// image is skipped with a warning (a drawing cannot make the loader read /dev or ~/.ssh).
  bool images_anywhere = false;
};

/// Loads an SVG file. Errors (unreadable file, malformed XML, root not <svg>, too
/// complex) name the file and the line. Unsupported features become warnings.
Result<Character> load_svg_file(const std::string& path, const SvgOptions& options = {});

/// Same, from text in memory; `name` is used in messages.
Result<Character> load_svg_string(std::string_view text, const std::string& name,
                                  const SvgOptions& options = {});

}  // namespace mar
