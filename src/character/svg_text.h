// SVG text as shapes: a run of text shaped in the font fontconfig picks for its family, weight
// and style (HarfBuzz), each glyph's outline (FreeType, unhinted, as librsvg draws it) turned
// into path commands, so text deforms with the character like any other shape.
#pragma once

#include "character/svg_parse.h"

#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace mar::svg {

struct FontRequest {
  std::string family;  ///< font-family as written: a comma-separated list, quoted or not
  int weight = 400;    ///< 100 .. 900
  bool italic = false;
};

/// One loader's fonts: matched once per request, each face opened once (at most 16 of them).
class TextShaper {
 public:
  TextShaper();
  ~TextShaper();
  TextShaper(const TextShaper&) = delete;
  TextShaper& operator=(const TextShaper&) = delete;

  /// Shapes `utf8` in the font for `font` at `size` user units. Appends each glyph's outline,
  /// placed from `origin` (the baseline's start, y down), to `out` when it is not null (no
  /// further glyph once it holds `max_commands`), and returns the run's advance;
  /// `letter_spacing` is added after each character. False (with `problem` said) when no font
  /// can be found; true with `problem` said when another font stood in (past 64 asked for).
  bool shape(const FontRequest& font, double size, std::string_view utf8, double letter_spacing, const Vec2& origin,
             std::vector<PathCmd>* out, size_t max_commands, double& advance, std::string& problem);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The characters of `utf8` as SVG lays out text with xml:space="default": newlines removed,
/// tabs as spaces, runs of spaces as one. `space_before` says the text before ended in a space
/// (a leading space is then dropped too); it is updated.
std::string collapse_white_space(std::string_view utf8, bool& space_before);

}  // namespace mar::svg
