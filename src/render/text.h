// Text for the performer's overlays (the HUD): the printable ASCII glyphs of a TrueType font
// (SDL2_ttf; DejaVu Sans Mono from Debian's fonts-dejavu-core) rendered once, at load, into a
// texture of the window's renderer. A line of text is then one copy per glyph: no font work and
// no allocation in a frame.
#pragma once

#include "base/result.h"

#include <SDL2/SDL_pixels.h>
#include <SDL2/SDL_rect.h>

#include <array>
#include <memory>
#include <string>
#include <string_view>

struct SDL_Renderer;
struct SDL_Texture;

namespace mar {

/// The font the HUD uses: DejaVu Sans Mono where fonts-dejavu-core puts it (or
/// $MARIONETTE_FONT); empty when none is installed.
std::string default_font_path();

class GlyphAtlas {
 public:
  /// Renders the glyphs of `font_path` at `px` pixels for renderer `r` (whose textures it makes).
  static Result<std::unique_ptr<GlyphAtlas>> load(SDL_Renderer* r, const std::string& font_path, int px);
  ~GlyphAtlas();
  GlyphAtlas(const GlyphAtlas&) = delete;
  GlyphAtlas& operator=(const GlyphAtlas&) = delete;

  /// Draws `text` (bytes outside printable ASCII show as '?') with its top-left corner at
  /// (x, y) in colour `c`; returns the width drawn.
  int draw(SDL_Renderer* r, int x, int y, std::string_view text, SDL_Color c) const;
  /// The width `text` would take.
  int width(std::string_view text) const;
  int line_height() const { return line_; }

 private:
  GlyphAtlas() = default;
  static constexpr int kFirst = 32, kCount = 95;
  SDL_Texture* tex_ = nullptr;
  std::array<SDL_Rect, kCount> glyph_{};  ///< in the texture
  std::array<int, kCount> advance_{};
  int line_ = 0;
};

}  // namespace mar
