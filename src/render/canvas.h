// One drawing target for every mode: the canvas, premultiplied RGBA8 pixels of a fixed size,
// drawn with the anti-aliased rasterizer (render/raster.h) — or, to compare, SDL's aliased
// software renderer. Offscreen, that is all. A window shows the canvas scaled to fit,
// letterboxed, whatever its own size; overlays for the performer (the HUD) are drawn on the
// window after the canvas, never into it, so dumps and outputs never carry them.
//
// In a window with an accelerated renderer (OpenGL, GLES2) the canvas is a texture the GPU
// draws into instead: the same triangles with a one-pixel fringe for anti-aliasing
// (DrawList::fringe; ask wants_fringe()), read back only when someone reads the pixels.
#pragma once

#include "character/character.h"
#include "render/composite.h"
#include "render/image.h"
#include "render/raster.h"
#include "render/tessellate.h"

#include <SDL2/SDL_rect.h>

#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

struct SDL_Renderer;
struct SDL_Surface;
struct SDL_Texture;
struct SDL_Window;

namespace mar {

/// How a window opens.
struct WindowOptions {
  std::string title = "marionette";
  int width = 0, height = 0;    ///< the window's size (0: the canvas's)
  bool fullscreen = false;
  bool software = false;        ///< SDL's software renderer instead of the GPU's
  /// With an accelerated renderer, the canvas is a render target the GPU draws into (fringe
  /// anti-aliasing, DrawList::fringe); false keeps the software rasterizer and uploads its pixels.
  bool gpu = true;
  int screen = -1;              ///< screen index (-1: SDL's choice)
  std::string screen_name;      ///< or a substring of its name (case-insensitive)
  /// A window with an alpha channel (X11: an ARGB visual, premultiplied, as compositors and
  /// OBS's window capture read it). Where the system gives none, the window shows the canvas
  /// over `fallback` instead (the canvas itself stays transparent) and `note` says so.
  bool transparent = false;
  Rgba fallback{0, 1, 0, 1};
  /// present() waits for the display's refresh (no tearing); where the renderer cannot, `note` says so.
  bool vsync = false;
  /// How long to keep asking for a display SDL cannot reach yet (an X server still starting at
  /// boot, or one too busy to answer), in seconds, before window() fails and says so.
  double display_wait_s = 1.0;
};

/// A screen SDL sees.
struct ScreenInfo {
  int index = 0;
  std::string name;
  int width = 0, height = 0;  ///< its desktop mode
};
/// The screens, or an empty list with `error` set when there is no display.
std::vector<ScreenInfo> list_screens(std::string* error);
/// Whether there is a display to open a window on: X, Wayland, or a video driver named
/// (SDL_VIDEODRIVER, as the kiosk unit names kmsdrm with neither); SDL's offscreen and dummy
/// drivers show nothing.
bool display_named();
/// Starts SDL's video (SDL_InitSubSystem): "" when a display is reached, else why not. A fall
/// back to SDL's offscreen driver that was not asked for (SDL_VIDEODRIVER) is no display; it is
/// asked again for up to `wait_s` seconds.
std::string start_video(double wait_s);
/// The screen a name or index picks among `screens` (-1: none matches).
int pick_screen(const std::vector<ScreenInfo>& screens, int index, const std::string& name);

class Canvas {
 public:
  /// Offscreen: a canvas of width x height. Needs no display.
  static Result<std::unique_ptr<Canvas>> offscreen(int width, int height);
  /// A window showing a canvas of width x height. `note` (when given) receives what the
  /// window could not have as asked (a screen that is not there, an alpha channel), each
  /// part named after its [display] key.
  static Result<std::unique_ptr<Canvas>> window(const WindowOptions& o, int width, int height, std::string* note = nullptr);
  ~Canvas();
  Canvas(const Canvas&) = delete;
  Canvas& operator=(const Canvas&) = delete;

  /// The canvas's size (not the window's).
  int width() const { return width_; }
  int height() const { return height_; }
  bool is_window() const { return window_ != nullptr; }
  /// Anti-aliased (the default) or SDL's aliased software triangles.
  void set_antialias(bool on) { antialias_ = on; }
  /// Makes now what drawing layers nested `depth` deep needs (the software rasterizer's buffers).
  void reserve_layers(size_t depth) {
    if (!gpu_) compositor_.reserve(depth, width(), height());
  }
  bool antialias() const { return antialias_; }
  /// Whether draw() wants its list built with fringes (the GPU draws the canvas, anti-aliased).
  bool wants_fringe() const { return gpu_ && antialias_; }
  /// Whether the GPU draws the canvas (a window with an accelerated renderer).
  bool gpu() const { return gpu_; }

  /// Fills the whole canvas with a straight-alpha colour (alpha 0 = transparent).
  void clear(const Rgba& background);
  /// A picture that clear_to_underlay() puts under each frame: what does not move (a show's
  /// scenery), drawn once. Premultiplied RGBA8 of exactly width() x height(); false (and
  /// nothing kept) otherwise. On the GPU it becomes a texture.
  bool set_underlay(std::vector<std::uint8_t> premultiplied);
  bool has_underlay() const { return !underlay_px_.empty(); }
  /// The underlay, copied over the whole canvas (no blending). No allocation.
  void clear_to_underlay();
  /// Draws the triangles in order; returns an error message or empty.
  std::string draw(const DrawList& list);
  /// Canvas pixels as premultiplied RGBA8 (exactly what blending produced).
  std::vector<std::uint8_t> read_premultiplied();
  /// The canvas pixels in place (premultiplied RGBA8, `stride` bytes a row).
  PixelTarget pixels();

  // ---- window ----
  /// Puts the canvas into the window, scaled to fit and letterboxed (once a frame; present()
  /// does it when it was not done). Overlays are drawn on window_renderer() after it.
  void compose();
  /// Shows the frame (window) — no-op offscreen.
  void present();
  SDL_Renderer* window_renderer() { return wrenderer_; }
  /// Whether present() waits for the refresh (the renderer said so), and the display's refresh
  /// rate in Hz (0: not known).
  bool vsync() const { return vsync_; }
  int refresh_hz() const;
  SDL_Window* sdl_window() { return window_; }
  /// The window's drawable size, and where the canvas shows in it.
  int window_width() const { return ww_; }
  int window_height() const { return wh_; }
  SDL_Rect canvas_rect() const { return shown_; }
  /// The window's pixels after compose() (and any overlay), premultiplied RGBA8, window-sized.
  std::vector<std::uint8_t> read_window();
  /// Whether the window has an alpha channel (transparent windows).
  bool window_alpha() const { return window_alpha_; }
  /// The screen the window is on (-1 offscreen).
  int screen() const;
  /// The window renderer's name ("software", "opengl", "opengles2", ...), empty offscreen.
  std::string renderer_name() const;

 private:
  Canvas() = default;
  SDL_Texture* texture_for(const Texture* t);
  bool make_canvas(int width, int height, std::string* err);

  int width_ = 0, height_ = 0;
  bool antialias_ = true;
  Rasterizer raster_;
  Compositor compositor_;  ///< layers (DrawList::layers) on the software rasterizer
  std::string draw_software(const DrawList& list, const DrawList::Batch& b, SDL_Texture* tex);
  std::string draw_gpu(const DrawList& list);
  SDL_Texture* gpu_texture_for(const Texture* t, bool premultiplied);
  void place();  ///< where the canvas shows in the window
  bool gpu_ = false;
  bool vsync_ = false;
  SDL_Texture* target_ = nullptr;  ///< the canvas on the GPU (gpu_)
  std::unordered_map<const Texture*, SDL_Texture*> gpu_textures_[2];  ///< straight, premultiplied
  std::vector<std::uint8_t> upload_;  ///< a texture being premultiplied
  SDL_BlendMode premultiplied_ = SDL_BLENDMODE_INVALID;  ///< "over" for premultiplied colours
  void make_white();
  SDL_Texture* white_ = nullptr;  ///< one white texel (draw_software)
  // SDL's software renderer gets every triangle with its own vertices (see draw_software());
  // these keep their capacity, so drawing allocates nothing once warmed up.
  std::vector<SDL_Vertex> sw_vertices_;
  std::vector<int> sw_indices_;
  SDL_Surface* surface_ = nullptr;    ///< the canvas
  std::vector<std::uint8_t> underlay_px_;  ///< set_underlay()'s picture (software copy)
  SDL_Texture* underlay_tex_ = nullptr;    ///< ...and on the GPU
  SDL_Renderer* renderer_ = nullptr;  ///< SDL's software renderer on the canvas (clear, aliased mode)
  std::unordered_map<const Texture*, SDL_Texture*> textures_;
  // window
  SDL_Window* window_ = nullptr;
  SDL_Renderer* wrenderer_ = nullptr;
  SDL_Texture* shown_tex_ = nullptr;  ///< the canvas, uploaded each frame
  int ww_ = 0, wh_ = 0;
  SDL_Rect shown_{0, 0, 0, 0};
  bool composed_ = false;
  bool window_alpha_ = false;
  bool backdrop_on_ = false;                ///< a transparent show where the window has no alpha
  std::uint32_t backdrop_ = 0;              ///< its chroma colour (opaque, packed RGBA)
  std::vector<std::uint8_t> backdrop_px_;   ///< the canvas over it (canvas-sized)
};

/// Maps the document rectangle [0, w] x [0, h] into a target of tw x th pixels,
/// uniformly scaled and centred.
Affine2 fit_view(double w, double h, int tw, int th, double margin_px = 0);

struct RenderOptions {
  int width = 0, height = 0;       ///< output size; 0 = document size
  Rgba background{0, 0, 0, 0};     ///< alpha 0 = transparent
  int supersample = 1;             ///< 1, 2 or 4
  bool antialias = true;           ///< false: SDL's aliased triangles (a reference at 4x)
  double tolerance_px = 0.2;
};

/// Renders a character offscreen (rest pose, or per-shape `positions`) into a
/// straight-alpha image, supersampled and reduced when asked.
Result<Image> render_character(const Character& ch, const CharacterMesh& mesh,
                               const RenderOptions& options, std::span<const Points> positions = {});

}  // namespace mar
