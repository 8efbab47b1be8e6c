// One drawing target for both modes: an offscreen surface (software renderer, no display,
// deterministic pixels) or an SDL2 window. The same DrawList draws on either.
#pragma once

#include "character/character.h"
#include "render/image.h"
#include "render/tessellate.h"

#include <memory>
#include <string>
#include <unordered_map>

struct SDL_Renderer;
struct SDL_Surface;
struct SDL_Texture;
struct SDL_Window;

namespace mar {

class Canvas {
 public:
  /// Offscreen: ABGR8888 surface + SDL software renderer. Needs no display.
  static Result<std::unique_ptr<Canvas>> offscreen(int width, int height);
  /// A window (SDL video must be available); `software` pins the software renderer; `display`:
  /// the display index to open it on (-1: SDL's choice).
  static Result<std::unique_ptr<Canvas>> window(const std::string& title, int width, int height,
                                                bool fullscreen, bool software, int display = -1);
  ~Canvas();
  Canvas(const Canvas&) = delete;
  Canvas& operator=(const Canvas&) = delete;

  int width() const { return width_; }
  int height() const { return height_; }
  bool is_window() const { return window_ != nullptr; }

  /// Fills the whole target with a straight-alpha colour (alpha 0 = transparent).
  void clear(const Rgba& background);
  /// Draws the triangles in order; returns an error message or empty.
  std::string draw(const DrawList& list);
  /// Target pixels as premultiplied RGBA8 (exactly what blending produced).
  std::vector<std::uint8_t> read_premultiplied();
  /// Shows the frame (window) — no-op offscreen.
  void present();
  /// The window's current drawable size may change; offscreen sizes never do.
  void refresh_size();

  SDL_Renderer* renderer() { return renderer_; }

 private:
  Canvas() = default;
  SDL_Texture* texture_for(const Texture* t);

  int width_ = 0, height_ = 0;
  bool software_ = false;
  std::string draw_software(const DrawList& list, const DrawList::Batch& b, SDL_Texture* tex);
  void make_white();
  SDL_Texture* white_ = nullptr;  ///< software renderers: one white texel (draw_software)
  // Software renderers get every triangle with its own vertices (see draw_software()); these
  // keep their capacity, so drawing allocates nothing once warmed up.
  std::vector<SDL_Vertex> sw_vertices_;
  std::vector<int> sw_indices_;
  SDL_Window* window_ = nullptr;
  SDL_Surface* surface_ = nullptr;
  SDL_Renderer* renderer_ = nullptr;
  std::unordered_map<const Texture*, SDL_Texture*> textures_;
};

/// Maps the document rectangle [0, w] x [0, h] into a target of tw x th pixels,
/// uniformly scaled and centred.
Affine2 fit_view(double w, double h, int tw, int th, double margin_px = 0);

struct RenderOptions {
  int width = 0, height = 0;       ///< output size; 0 = document size
  Rgba background{0, 0, 0, 0};     ///< alpha 0 = transparent
  int supersample = 1;             ///< 1, 2 or 4
  double tolerance_px = 0.2;
};

/// Renders a character offscreen (rest pose, or per-shape `positions`) into a
/// straight-alpha image, supersampled and reduced when asked.
Result<Image> render_character(const Character& ch, const CharacterMesh& mesh,
                               const RenderOptions& options, std::span<const Points> positions = {});

}  // namespace mar
