#include "render/text.h"

#include <SDL2/SDL.h>
#include <SDL2/SDL_ttf.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

namespace mar {

std::string default_font_path() {
  if (const char* f = std::getenv("MARIONETTE_FONT"); f && *f) return f;
  for (const char* p : {"/usr/share/fonts/truetype/dejavu/DejaVuSansMono.ttf", "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"})
    if (std::filesystem::exists(p)) return p;
  return {};
}

Result<std::unique_ptr<GlyphAtlas>> GlyphAtlas::load(SDL_Renderer* r, const std::string& font_path, int px) {
  using R = Result<std::unique_ptr<GlyphAtlas>>;
  if (font_path.empty()) return R::failure("no font (install fonts-dejavu-core, or set MARIONETTE_FONT)");
  if (!TTF_WasInit() && TTF_Init() != 0) return R::failure(std::string("SDL_ttf: ") + TTF_GetError());
  TTF_Font* font = TTF_OpenFont(font_path.c_str(), px);
  if (!font) return R::failure(font_path + ": " + TTF_GetError());
  std::unique_ptr<GlyphAtlas> a(new GlyphAtlas());
  a->line_ = TTF_FontLineSkip(font);
  // One row of glyphs, each in a cell as wide as its own surface.
  std::array<SDL_Surface*, kCount> glyphs{};
  int total = 0, height = 1;
  for (int i = 0; i < kCount; ++i) {
    const Uint16 ch = Uint16(kFirst + i);
    int minx, maxx, miny, maxy, adv = 0;
    TTF_GlyphMetrics(font, ch, &minx, &maxx, &miny, &maxy, &adv);
    a->advance_[size_t(i)] = adv;
    glyphs[size_t(i)] = ch == ' ' ? nullptr : TTF_RenderGlyph_Blended(font, ch, SDL_Color{255, 255, 255, 255});
    if (glyphs[size_t(i)]) {
      total += glyphs[size_t(i)]->w + 1;
      height = std::max(height, glyphs[size_t(i)]->h);
    }
  }
  TTF_CloseFont(font);
  SDL_Surface* sheet = SDL_CreateRGBSurfaceWithFormat(0, std::max(1, total), height, 32, SDL_PIXELFORMAT_ARGB8888);
  std::string err;
  if (!sheet) err = std::string("glyph sheet: ") + SDL_GetError();
  int x = 0;
  for (int i = 0; i < kCount; ++i) {
    SDL_Surface* g = glyphs[size_t(i)];
    if (!g) continue;
    if (sheet) {
      SDL_SetSurfaceBlendMode(g, SDL_BLENDMODE_NONE);
      SDL_Rect dst{x, 0, g->w, g->h};
      SDL_BlitSurface(g, nullptr, sheet, &dst);
      a->glyph_[size_t(i)] = dst;
    }
    x += g->w + 1;
    SDL_FreeSurface(g);
  }
  if (sheet) {
    a->tex_ = SDL_CreateTextureFromSurface(r, sheet);
    if (!a->tex_) err = std::string("glyph texture: ") + SDL_GetError();
    SDL_FreeSurface(sheet);
  }
  if (!err.empty()) return R::failure(err);
  SDL_SetTextureBlendMode(a->tex_, SDL_BLENDMODE_BLEND);
  return R::success(std::move(a));
}

GlyphAtlas::~GlyphAtlas() {
  if (tex_) SDL_DestroyTexture(tex_);
}

int GlyphAtlas::width(std::string_view text) const {
  int w = 0;
  for (char c : text) {
    const int i = (c >= kFirst && c < kFirst + kCount) ? c - kFirst : '?' - kFirst;
    w += advance_[size_t(i)];
  }
  return w;
}

int GlyphAtlas::draw(SDL_Renderer* r, int x, int y, std::string_view text, SDL_Color c) const {
  SDL_SetTextureColorMod(tex_, c.r, c.g, c.b);
  SDL_SetTextureAlphaMod(tex_, c.a);
  const int x0 = x;
  for (char ch : text) {
    const int i = (ch >= kFirst && ch < kFirst + kCount) ? ch - kFirst : '?' - kFirst;
    const SDL_Rect& g = glyph_[size_t(i)];
    if (g.w > 0) {
      SDL_Rect dst{x, y, g.w, g.h};
      SDL_RenderCopy(r, tex_, &g, &dst);
    }
    x += advance_[size_t(i)];
  }
  return x - x0;
}

}  // namespace mar
