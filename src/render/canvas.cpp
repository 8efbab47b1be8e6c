#include "render/canvas.h"

#include "character/color.h"
#include "render/x11_visual.h"

#include <SDL2/SDL.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>

namespace mar {

bool Canvas::make_canvas(int width, int height, std::string* err) {
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384) {
    *err = "canvas size " + std::to_string(width) + "x" + std::to_string(height) + " out of range (1..16384)";
    return false;
  }
  width_ = width;
  height_ = height;
  surface_ = SDL_CreateRGBSurfaceWithFormat(0, width, height, 32, SDL_PIXELFORMAT_ABGR8888);
  if (!surface_) {
    *err = std::string("cannot create surface: ") + SDL_GetError();
    return false;
  }
  renderer_ = SDL_CreateSoftwareRenderer(surface_);
  if (!renderer_) {
    *err = std::string("cannot create software renderer: ") + SDL_GetError();
    return false;
  }
  SDL_SetRenderDrawBlendMode(renderer_, SDL_BLENDMODE_BLEND);
  make_white();
  return true;
}

Result<std::unique_ptr<Canvas>> Canvas::offscreen(int width, int height) {
  using R = Result<std::unique_ptr<Canvas>>;
  std::unique_ptr<Canvas> c(new Canvas());
  std::string err;
  if (!c->make_canvas(width, height, &err)) return R::failure(err);
  return R::success(std::move(c));
}

namespace {

bool offscreen_driver() {
  const char* d = SDL_GetCurrentVideoDriver();
  return d && (std::strcmp(d, "offscreen") == 0 || std::strcmp(d, "dummy") == 0);
}

}  // namespace

bool display_named() {
  const char* x = std::getenv("DISPLAY");
  const char* wl = std::getenv("WAYLAND_DISPLAY");
  const char* driver = std::getenv("SDL_VIDEODRIVER");
  const bool named = driver && *driver && !std::strstr(driver, "offscreen") && !std::strstr(driver, "dummy");
  return (x && *x) || (wl && *wl) || named;
}

std::vector<ScreenInfo> list_screens(std::string* error) {
  std::vector<ScreenInfo> out;
  // No display to ask (and no driver named, as a KMS/DRM kiosk names kmsdrm): SDL is not asked,
  // since its Wayland probe prints an error of its own about XDG_RUNTIME_DIR.
  if (!display_named()) {
    if (error) *error = "no display (DISPLAY and WAYLAND_DISPLAY are unset)";
    return out;
  }
  if (SDL_InitSubSystem(SDL_INIT_VIDEO) != 0) {
    if (error) *error = std::string("no display: ") + SDL_GetError();
    return out;
  }
  // With no display SDL falls back to its offscreen driver, whose "screen" shows nothing.
  if (offscreen_driver()) {
    if (error) *error = "no display (DISPLAY and WAYLAND_DISPLAY are unset)";
    SDL_QuitSubSystem(SDL_INIT_VIDEO);
    return out;
  }
  for (int i = 0; i < SDL_GetNumVideoDisplays(); ++i) {
    ScreenInfo s;
    s.index = i;
    if (const char* n = SDL_GetDisplayName(i)) s.name = n;
    SDL_DisplayMode m;
    if (SDL_GetDesktopDisplayMode(i, &m) == 0) {
      s.width = m.w;
      s.height = m.h;
    }
    out.push_back(s);
  }
  SDL_QuitSubSystem(SDL_INIT_VIDEO);
  if (SDL_WasInit(SDL_INIT_EVERYTHING) == 0) SDL_Quit();  // (and SDL's D-Bus connection)
  return out;
}

std::string start_video(double wait_s) {
  // SDL falls back to its offscreen driver when it cannot reach the display it was given: a
  // "window" there shows nothing (a kiosk ran a whole show so, saying it was in a window, when
  // its X server did not answer at once). Unless that driver was asked for, it is no display:
  // asked again every 0.2 s for wait_s, then said.
  const char* asked = std::getenv("SDL_VIDEODRIVER");
  const bool wants_offscreen = asked && (std::strstr(asked, "offscreen") || std::strstr(asked, "dummy"));
  // Asked again, an X display is asked for by name: SDL's Wayland probe, when there is no
  // Wayland, prints an error of its own each time.
  const bool x_only = std::getenv("DISPLAY") && !std::getenv("WAYLAND_DISPLAY") && !(asked && *asked);
  auto env = [](const char* name) {
    const char* v = std::getenv(name);
    return v && *v ? std::string(" ") + name + "=" + v : std::string();
  };
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(std::max(0.0, wait_s));
  std::string why;
  for (int attempt = 0;; ++attempt) {
    if (attempt == 1 && x_only) SDL_SetHint(SDL_HINT_VIDEODRIVER, "x11");
    const bool started = SDL_InitSubSystem(SDL_INIT_VIDEO) == 0;
    if (started && (!offscreen_driver() || wants_offscreen)) break;
    if (started) SDL_QuitSubSystem(SDL_INIT_VIDEO);
    if (std::chrono::steady_clock::now() >= until) {
      char secs[32];
      std::snprintf(secs, sizeof secs, "%.1f", wait_s);
      why = "no display: SDL could not reach" + env("DISPLAY") + env("WAYLAND_DISPLAY") + env("SDL_VIDEODRIVER") + " in " + secs + " s" +
            (started ? std::string() : std::string(" (") + SDL_GetError() + ")");
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  if (x_only) SDL_ResetHint(SDL_HINT_VIDEODRIVER);
  return why;
}

int pick_screen(const std::vector<ScreenInfo>& screens, int index, const std::string& name) {
  if (!name.empty()) {
    auto lower = [](std::string s) {
      for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
      return s;
    };
    for (const ScreenInfo& s : screens)
      if (lower(s.name).find(lower(name)) != std::string::npos) return s.index;
    return -1;
  }
  for (const ScreenInfo& s : screens)
    if (s.index == index) return index;
  return -1;
}

Result<std::unique_ptr<Canvas>> Canvas::window(const WindowOptions& o, int width, int height, std::string* note) {
  using R = Result<std::unique_ptr<Canvas>>;
  std::unique_ptr<Canvas> c(new Canvas());
  std::string err;
  if (!c->make_canvas(width, height, &err)) return R::failure(err);
  // The screen: by name or index; one that is not there is said, and SDL's choice used.
  // Video first, then the screens: list_screens() alone would shut video down and start it again,
  // which on a busy machine found X "not available" (a kiosk then ran in no window at all).
  if (const std::string e = start_video(o.display_wait_s); !e.empty()) return R::failure(e);
  int screen = -1;
  if (o.screen >= 0 || !o.screen_name.empty()) {
    const auto screens = list_screens(nullptr);
    screen = pick_screen(screens, o.screen, o.screen_name);
    if (screen < 0 && note) {
      *note = "screen: no screen " + (o.screen_name.empty() ? std::to_string(o.screen) : "named like '" + o.screen_name + "'") +
              " among the " + std::to_string(screens.size()) + " there (marionette devices lists them); using the first";
    }
  }
  Uint32 flags = SDL_WINDOW_RESIZABLE | SDL_WINDOW_ALLOW_HIGHDPI;
  // Fullscreen on an X display with no window manager (a kiosk started by xinit): nothing would
  // turn SDL's fullscreen window to the screen's size, and it would stay at the show's. The
  // window is made borderless with the screen's bounds instead.
  SDL_Rect full{};
  const bool by_hand = o.fullscreen && std::string(SDL_GetCurrentVideoDriver()) == "x11" && x11_without_window_manager() &&
                       SDL_GetDisplayBounds(std::max(0, screen), &full) == 0;
  if (o.fullscreen && !by_hand) flags |= SDL_WINDOW_FULLSCREEN_DESKTOP;
  if (by_hand) flags |= SDL_WINDOW_BORDERLESS;
  bool forced_visual = false;
  if (o.transparent && std::string(SDL_GetCurrentVideoDriver()) == "x11") {
    if (const unsigned long id = x11_argb_visual()) {
      SDL_SetHint(SDL_HINT_VIDEO_X11_WINDOW_VISUALID, std::to_string(id).c_str());
      SDL_GL_SetAttribute(SDL_GL_ALPHA_SIZE, 8);
      forced_visual = true;
    }
  }
  const int pos = screen >= 0 ? int(SDL_WINDOWPOS_CENTERED_DISPLAY(screen)) : int(SDL_WINDOWPOS_CENTERED);
  c->window_ = by_hand ? SDL_CreateWindow(o.title.c_str(), full.x, full.y, full.w, full.h, flags)
                       : SDL_CreateWindow(o.title.c_str(), pos, pos, o.width > 0 ? o.width : width, o.height > 0 ? o.height : height, flags);
  if (!c->window_) {
    if (forced_visual) SDL_SetHint(SDL_HINT_VIDEO_X11_WINDOW_VISUALID, "");
    SDL_QuitSubSystem(SDL_INIT_VIDEO);
    return R::failure(std::string("cannot open window: ") + SDL_GetError());
  }
  // Batched: drawing on the window (the canvas, the HUD) is queued and handed to the driver at
  // present. SDL turns batching off when a render driver is named (SDL_RENDER_DRIVER), which
  // would send every glyph of the HUD to the driver on its own.
  SDL_SetHint(SDL_HINT_RENDER_BATCHING, "1");
  const Uint32 sync = o.vsync ? SDL_RENDERER_PRESENTVSYNC : 0;
  c->wrenderer_ = SDL_CreateRenderer(c->window_, -1, (o.software ? SDL_RENDERER_SOFTWARE : SDL_RENDERER_ACCELERATED) | sync);
  if (!c->wrenderer_ && !o.software) c->wrenderer_ = SDL_CreateRenderer(c->window_, -1, SDL_RENDERER_SOFTWARE | sync);
  if (forced_visual) SDL_SetHint(SDL_HINT_VIDEO_X11_WINDOW_VISUALID, "");  // (an OpenGL renderer re-creates the window)
  if (!c->wrenderer_) return R::failure(std::string("cannot create renderer: ") + SDL_GetError());
  c->premultiplied_ = SDL_ComposeCustomBlendMode(SDL_BLENDFACTOR_ONE, SDL_BLENDFACTOR_ONE_MINUS_SRC_ALPHA, SDL_BLENDOPERATION_ADD,
                                                 SDL_BLENDFACTOR_ONE, SDL_BLENDFACTOR_ONE_MINUS_SRC_ALPHA, SDL_BLENDOPERATION_ADD);
  SDL_RendererInfo info;
  // (SDL's software renderer on X11 says PRESENTVSYNC even when it was not asked for and does not wait.)
  if (SDL_GetRendererInfo(c->wrenderer_, &info) == 0) c->vsync_ = o.vsync && (info.flags & SDL_RENDERER_PRESENTVSYNC) != 0;
  if (o.vsync && !c->vsync_ && note)
    *note += std::string(note->empty() ? "" : "; ") + "vsync: the " + info.name + " renderer presents without waiting for the refresh";
  // The GPU draws the canvas where the renderer is an accelerated one with render targets.
  if (o.gpu && SDL_GetRendererInfo(c->wrenderer_, &info) == 0 && !(info.flags & SDL_RENDERER_SOFTWARE) &&
      SDL_RenderTargetSupported(c->wrenderer_)) {
    c->target_ = SDL_CreateTexture(c->wrenderer_, SDL_PIXELFORMAT_ABGR8888, SDL_TEXTUREACCESS_TARGET, width, height);
    if (c->target_ && SDL_SetTextureBlendMode(c->target_, c->premultiplied_) == 0) {
      SDL_SetTextureScaleMode(c->target_, SDL_ScaleModeLinear);
      c->gpu_ = true;
    } else if (note) {
      *note += std::string(note->empty() ? "" : "; ") + "gpu: the " + info.name + " renderer cannot draw the " + std::to_string(width) + "x" +
               std::to_string(height) + " canvas (" + SDL_GetError() + "); it is drawn in software and uploaded";
    }
  }
  c->shown_tex_ = SDL_CreateTexture(c->wrenderer_, SDL_PIXELFORMAT_ABGR8888, SDL_TEXTUREACCESS_STREAMING, width, height);
  if (!c->shown_tex_) return R::failure(std::string("cannot create the canvas texture: ") + SDL_GetError());
  SDL_SetTextureBlendMode(c->shown_tex_, SDL_BLENDMODE_NONE);
  SDL_SetTextureScaleMode(c->shown_tex_, SDL_ScaleModeLinear);
  // An alpha channel: an X window of depth 32 drawn by OpenGL with alpha bits (SDL's software
  // renderer presents through an XRGB surface, whose fourth byte is not the canvas's alpha).
  int alpha_bits = 0;
  const bool gl = c->renderer_name().rfind("opengl", 0) == 0;
  if (gl) SDL_GL_GetAttribute(SDL_GL_ALPHA_SIZE, &alpha_bits);
  c->window_alpha_ = forced_visual && gl && alpha_bits >= 8 && x11_window_depth(c->window_) == 32;
  if (o.transparent && !c->window_alpha_) {
    // No alpha here: the canvas (still transparent for dumps and outputs) over a chroma colour.
    c->backdrop_on_ = true;
    auto byte = [](float v) { return std::uint32_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
    c->backdrop_ = byte(o.fallback.r) | byte(o.fallback.g) << 8 | byte(o.fallback.b) << 16 | 255u << 24;
    c->backdrop_px_.resize(size_t(width) * size_t(height) * 4);
    if (note)
      *note += std::string(note->empty() ? "" : "; ") + "background: this display gives windows no alpha channel (" + SDL_GetCurrentVideoDriver() +
              (!forced_visual ? ", no ARGB visual" : !gl ? ", not drawn with OpenGL" : ", no alpha in its OpenGL surface") +
              "): the window shows the stage on " +
              color_hex(o.fallback) + " instead; dumps and outputs stay transparent";
  }
  return R::success(std::move(c));
}

int Canvas::screen() const { return window_ ? SDL_GetWindowDisplayIndex(window_) : -1; }

Canvas::~Canvas() {
  for (auto& [k, t] : textures_) SDL_DestroyTexture(t);
  for (auto& cache : gpu_textures_)
    for (auto& [k, t] : cache) SDL_DestroyTexture(t);
  if (target_) SDL_DestroyTexture(target_);
  if (white_) SDL_DestroyTexture(white_);
  if (underlay_tex_) SDL_DestroyTexture(underlay_tex_);
  if (renderer_) SDL_DestroyRenderer(renderer_);
  if (surface_) SDL_FreeSurface(surface_);
  if (shown_tex_) SDL_DestroyTexture(shown_tex_);
  if (wrenderer_) SDL_DestroyRenderer(wrenderer_);
  if (window_) {
    SDL_DestroyWindow(window_);
    SDL_QuitSubSystem(SDL_INIT_VIDEO);
    // Last subsystem gone: SDL_Quit also closes SDL's D-Bus connection.
    if (SDL_WasInit(SDL_INIT_EVERYTHING) == 0) SDL_Quit();
  }
}

// One white texel: translucent fills are drawn through it on software renderers (draw_software).
void Canvas::make_white() {
  white_ = SDL_CreateTexture(renderer_, SDL_PIXELFORMAT_ABGR8888, SDL_TEXTUREACCESS_STATIC, 1, 1);
  if (!white_) return;  // (then translucent fills go the allocating way)
  const Uint32 px = 0xffffffffu;
  SDL_UpdateTexture(white_, nullptr, &px, 4);
  SDL_SetTextureBlendMode(white_, SDL_BLENDMODE_BLEND);
}

void Canvas::clear(const Rgba& bg) {
  auto byte = [](float v) { return static_cast<Uint8>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
  composed_ = false;
  if (gpu_) {
    SDL_SetRenderTarget(wrenderer_, target_);
    SDL_SetRenderDrawBlendMode(wrenderer_, SDL_BLENDMODE_NONE);
    SDL_SetRenderDrawColor(wrenderer_, byte(bg.r * bg.a), byte(bg.g * bg.a), byte(bg.b * bg.a), byte(bg.a));
    SDL_RenderClear(wrenderer_);
    SDL_SetRenderDrawBlendMode(wrenderer_, SDL_BLENDMODE_BLEND);
    return;
  }
  // Stored premultiplied, which is what blending onto it then keeps.
  SDL_SetRenderDrawBlendMode(renderer_, SDL_BLENDMODE_NONE);
  SDL_SetRenderDrawColor(renderer_, byte(bg.r * bg.a), byte(bg.g * bg.a), byte(bg.b * bg.a), byte(bg.a));
  SDL_RenderClear(renderer_);
  SDL_SetRenderDrawBlendMode(renderer_, SDL_BLENDMODE_BLEND);
  composed_ = false;
}

bool Canvas::set_underlay(std::vector<std::uint8_t> px) {
  if (px.size() != static_cast<size_t>(width_) * static_cast<size_t>(height_) * 4) return false;
  if (underlay_tex_) SDL_DestroyTexture(underlay_tex_);
  underlay_tex_ = nullptr;
  if (gpu_) {
    underlay_tex_ = SDL_CreateTexture(wrenderer_, SDL_PIXELFORMAT_ABGR8888, SDL_TEXTUREACCESS_STATIC, width_, height_);
    if (!underlay_tex_ || SDL_UpdateTexture(underlay_tex_, nullptr, px.data(), width_ * 4) != 0) {
      if (underlay_tex_) SDL_DestroyTexture(underlay_tex_);
      underlay_tex_ = nullptr;
      return false;
    }
    SDL_SetTextureBlendMode(underlay_tex_, SDL_BLENDMODE_NONE);
  }
  underlay_px_ = std::move(px);
  return true;
}

void Canvas::clear_to_underlay() {
  composed_ = false;
  if (gpu_ && underlay_tex_) {
    SDL_SetRenderTarget(wrenderer_, target_);
    SDL_RenderCopy(wrenderer_, underlay_tex_, nullptr, nullptr);
    SDL_SetRenderDrawBlendMode(wrenderer_, SDL_BLENDMODE_BLEND);
    return;
  }
  auto* dst = static_cast<std::uint8_t*>(surface_->pixels);
  const size_t row = static_cast<size_t>(width_) * 4;
  for (int y = 0; y < height_; ++y)
    std::memcpy(dst + static_cast<size_t>(y) * static_cast<size_t>(surface_->pitch), underlay_px_.data() + static_cast<size_t>(y) * row, row);
}

PixelTarget Canvas::pixels() {
  if (gpu_) {  // read back from the GPU into the surface
    SDL_Texture* was = SDL_GetRenderTarget(wrenderer_);
    SDL_SetRenderTarget(wrenderer_, target_);
    SDL_RenderReadPixels(wrenderer_, nullptr, SDL_PIXELFORMAT_ABGR8888, surface_->pixels, surface_->pitch);
    SDL_SetRenderTarget(wrenderer_, was);
  }
  SDL_RenderFlush(renderer_);  // what SDL still has queued for the canvas goes first
  return {static_cast<std::uint8_t*>(surface_->pixels), width_, height_, surface_->pitch};
}

SDL_Texture* Canvas::texture_for(const Texture* t) {
  auto it = textures_.find(t);
  if (it != textures_.end()) return it->second;
  SDL_Texture* tex = SDL_CreateTexture(renderer_, SDL_PIXELFORMAT_ABGR8888, SDL_TEXTUREACCESS_STATIC,
                                       t->width, t->height);
  if (tex) {
    SDL_UpdateTexture(tex, nullptr, t->rgba.data(), t->width * 4);
    SDL_SetTextureBlendMode(tex, SDL_BLENDMODE_BLEND);
    // Linear filtering where the renderer has it (OpenGL). SDL 2.26's software renderer
    // samples nearest and stretches texture coordinates by up to one texel; at the size
    // of character textures that is not visible.
    SDL_SetTextureScaleMode(tex, SDL_ScaleModeLinear);
  }
  textures_.emplace(t, tex);
  return tex;
}

// Textures for the GPU, uploaded premultiplied for lists built with fringes (their modulation
// colours are premultiplied too: bilinear filtering then blends no dark halo in); straight
// for plain lists.
SDL_Texture* Canvas::gpu_texture_for(const Texture* t, bool premultiplied) {
  auto& cache = gpu_textures_[premultiplied ? 1 : 0];
  auto it = cache.find(t);
  if (it != cache.end()) return it->second;
  SDL_Texture* tex = SDL_CreateTexture(wrenderer_, SDL_PIXELFORMAT_ABGR8888, SDL_TEXTUREACCESS_STATIC, t->width, t->height);
  if (tex) {
    upload_.assign(t->rgba.begin(), t->rgba.end());
    if (premultiplied)
      for (size_t i = 0; i + 3 < upload_.size(); i += 4)
        for (size_t ch = 0; ch < 3; ++ch) upload_[i + ch] = std::uint8_t((upload_[i + ch] * upload_[i + 3] + 127) / 255);
    SDL_UpdateTexture(tex, nullptr, upload_.data(), t->width * 4);
    SDL_SetTextureBlendMode(tex, premultiplied ? premultiplied_ : SDL_BLENDMODE_BLEND);
    SDL_SetTextureScaleMode(tex, SDL_ScaleModeLinear);
  }
  cache.emplace(t, tex);
  return tex;
}

namespace {

// For renderers that draw no layers (the GPU, SDL's aliased triangles): [index_begin,
// index_end) drawn by `geometry` (a plain range of indices), each layer's content straight and
// its clip and mask left out. The GPU's list has a group's opacity multiplied into its shapes
// (build_draw_list); blur, shadows, clips and masks need the software rasterizer (a show whose
// character has them draws there).
template <class Geometry>
std::string straight(const DrawList& list, int index_begin, int index_end, size_t& layer, const Geometry& geometry) {
  int at = index_begin;
  while (layer < list.layers.size() && list.layers[layer].begin < index_end) {
    const DrawList::Layer& l = list.layers[layer++];
    if (l.begin < at) continue;
    if (std::string e = geometry(at, l.begin); !e.empty()) return e;
    at = l.mask_end;
    if (!(l.opacity > 0)) continue;
    if (std::string e = straight(list, l.begin, l.content_end, layer, geometry); !e.empty()) return e;
  }
  return geometry(at, index_end);
}

}  // namespace

// The GPU draws the list into the canvas texture: SDL queues the triangles (batched) and hands
// them to the driver at present or read-back.
std::string Canvas::draw_gpu(const DrawList& list) {
  SDL_SetRenderTarget(wrenderer_, target_);
  SDL_SetRenderDrawBlendMode(wrenderer_, SDL_BLENDMODE_BLEND);
  size_t layer = 0;
  return straight(list, 0, static_cast<int>(list.indices.size()), layer, [&](int from, int to) -> std::string {
    for (const DrawList::Batch& b : list.batches) {
      const int lo = std::max(b.first_index, from), hi = std::min(b.first_index + b.index_count, to);
      if (hi <= lo) continue;
      SDL_Texture* tex = b.texture ? gpu_texture_for(b.texture, list.fringe) : nullptr;
      if (b.texture && !tex) return std::string("cannot create texture: ") + SDL_GetError();
      if (SDL_RenderGeometry(wrenderer_, tex, list.vertices.data(), static_cast<int>(list.vertices.size()), list.indices.data() + lo,
                             hi - lo) != 0)
        return std::string("SDL_RenderGeometry failed: ") + SDL_GetError();
    }
    return {};
  });
}

std::string Canvas::draw(const DrawList& list) {
  composed_ = false;
  if (gpu_) return draw_gpu(list);
  if (antialias_) {
    if (list.layers.empty()) raster_.draw(list, pixels());
    else compositor_.draw(raster_, list, pixels());
    return {};
  }
  size_t layer = 0;
  return straight(list, 0, static_cast<int>(list.indices.size()), layer, [&](int from, int to) -> std::string {
    for (const DrawList::Batch& b : list.batches) {
      DrawList::Batch part = b;
      part.first_index = std::max(b.first_index, from);
      part.index_count = std::min(b.first_index + b.index_count, to) - part.first_index;
      if (part.index_count <= 0) continue;
      SDL_Texture* tex = b.texture ? texture_for(b.texture) : nullptr;
      if (b.texture && !tex) return std::string("cannot create texture: ") + SDL_GetError();
      if (std::string e = draw_software(list, part, tex); !e.empty()) return e;
    }
    return {};
  });
}

// SDL 2.26's software path redraws two consecutive triangles that share two vertex indices
// as an axis-aligned rectangle when its (loose) corner test passes, which it also does for
// sheared quads: distinct indices for every triangle avoid that. And it fills a blended
// untextured triangle through a temporary surface it allocates for each one
// (SDL_SW_FillTriangle): thousands of mallocs a frame. So, in runs: an opaque fill is drawn
// with blending off (the same pixels, written in place), and a translucent fill as the white
// texel modulated by its colour (SDL_SW_BlitTriangle blends in place). Textured triangles
// already blend in place.
std::string Canvas::draw_software(const DrawList& list, const DrawList::Batch& b, SDL_Texture* tex) {
  const int* idx = list.indices.data() + b.first_index;
  const auto& in = list.vertices;
  enum Way { Textured, Opaque, Translucent };
  auto way = [&](int k) {
    if (tex || !white_) return Textured;  // (no white texel: the blended fill as before)
    for (int j = 0; j < 3; ++j)
      if (in[static_cast<size_t>(idx[k + j])].color.a != 255) return Translucent;
    return Opaque;
  };
  for (int k = 0; k + 2 < b.index_count;) {
    const Way w = way(k);
    sw_vertices_.clear();
    sw_indices_.clear();
    for (; k + 2 < b.index_count && way(k) == w; k += 3)
      for (int j = 0; j < 3; ++j) {
        SDL_Vertex v = in[static_cast<size_t>(idx[k + j])];
        if (w == Translucent) v.tex_coord = {0.5f, 0.5f};
        sw_vertices_.push_back(v);
        sw_indices_.push_back(static_cast<int>(sw_indices_.size()));
      }
    SDL_SetRenderDrawBlendMode(renderer_, w == Opaque ? SDL_BLENDMODE_NONE : SDL_BLENDMODE_BLEND);
    const int rc = SDL_RenderGeometry(renderer_, w == Translucent ? white_ : tex, sw_vertices_.data(),
                                      static_cast<int>(sw_vertices_.size()), sw_indices_.data(),
                                      static_cast<int>(sw_indices_.size()));
    SDL_SetRenderDrawBlendMode(renderer_, SDL_BLENDMODE_BLEND);
    if (rc != 0) return std::string("SDL_RenderGeometry failed: ") + SDL_GetError();
  }
  return {};
}

std::vector<std::uint8_t> Canvas::read_premultiplied() {
  std::vector<std::uint8_t> px(static_cast<size_t>(width_) * height_ * 4);
  const PixelTarget t = pixels();
  for (int y = 0; y < height_; ++y) {
    const std::uint8_t* row = t.px + static_cast<size_t>(y) * static_cast<size_t>(t.stride);
    std::copy(row, row + static_cast<size_t>(width_) * 4, px.begin() + static_cast<long>(y) * width_ * 4);
  }
  return px;
}

void Canvas::compose() {
  if (!window_ || composed_) return;
  composed_ = true;
  if (gpu_) {
    SDL_SetRenderTarget(wrenderer_, nullptr);
    place();
    SDL_SetRenderDrawBlendMode(wrenderer_, SDL_BLENDMODE_NONE);
    SDL_SetRenderDrawColor(wrenderer_, 0, 0, 0, window_alpha_ ? 0 : 255);
    SDL_RenderClear(wrenderer_);
    if (backdrop_on_) {  // the canvas over the chroma colour
      SDL_SetRenderDrawColor(wrenderer_, backdrop_ & 0xFF, backdrop_ >> 8 & 0xFF, backdrop_ >> 16 & 0xFF, 255);
      SDL_RenderFillRect(wrenderer_, &shown_);
    }
    SDL_SetTextureBlendMode(target_, backdrop_on_ ? premultiplied_ : SDL_BLENDMODE_NONE);
    SDL_RenderCopy(wrenderer_, target_, nullptr, &shown_);
    SDL_SetRenderDrawBlendMode(wrenderer_, SDL_BLENDMODE_BLEND);
    return;
  }
  const PixelTarget t = pixels();
  if (backdrop_on_) {  // premultiplied canvas over the opaque chroma colour
    for (int y = 0; y < height_; ++y) {
      const std::uint8_t* s = t.px + size_t(y) * size_t(t.stride);
      std::uint8_t* d = backdrop_px_.data() + size_t(y) * size_t(width_) * 4;
      for (int x = 0; x < width_ * 4; x += 4) {
        const std::uint32_t k = 255u - s[x + 3];
        for (int ch = 0; ch < 3; ++ch) d[x + ch] = std::uint8_t(s[x + ch] + ((backdrop_ >> (8 * ch) & 0xFF) * k + 127) / 255);
        d[x + 3] = 255;
      }
    }
    SDL_UpdateTexture(shown_tex_, nullptr, backdrop_px_.data(), width_ * 4);
  } else {
    SDL_UpdateTexture(shown_tex_, nullptr, t.px, t.stride);
  }
  place();
  SDL_SetRenderDrawBlendMode(wrenderer_, SDL_BLENDMODE_NONE);
  SDL_SetRenderDrawColor(wrenderer_, 0, 0, 0, window_alpha_ ? 0 : 255);
  SDL_RenderClear(wrenderer_);
  SDL_RenderCopy(wrenderer_, shown_tex_, nullptr, &shown_);
  SDL_SetRenderDrawBlendMode(wrenderer_, SDL_BLENDMODE_BLEND);
}

// Scaled to fit, centred; the bars around it black (transparent in a window with alpha).
void Canvas::place() {
  SDL_GetRendererOutputSize(wrenderer_, &ww_, &wh_);
  const double s = std::min(double(ww_) / width_, double(wh_) / height_);
  const int w = std::max(1, int(std::lround(width_ * s))), h = std::max(1, int(std::lround(height_ * s)));
  shown_ = {(ww_ - w) / 2, (wh_ - h) / 2, w, h};
}

int Canvas::refresh_hz() const {
  SDL_DisplayMode m;
  if (!window_ || SDL_GetWindowDisplayMode(window_, &m) != 0) return 0;
  return m.refresh_rate;
}

void Canvas::present() {
  if (!window_) return;
  compose();
  SDL_RenderPresent(wrenderer_);
  composed_ = false;
}

std::vector<std::uint8_t> Canvas::read_window() {
  if (!window_) return {};
  compose();
  std::vector<std::uint8_t> px(static_cast<size_t>(ww_) * static_cast<size_t>(wh_) * 4);
  SDL_RenderReadPixels(wrenderer_, nullptr, SDL_PIXELFORMAT_ABGR8888, px.data(), ww_ * 4);
  return px;
}

std::string Canvas::renderer_name() const {
  SDL_RendererInfo info;
  if (!wrenderer_ || SDL_GetRendererInfo(wrenderer_, &info) != 0) return {};
  return info.name;
}

Affine2 fit_view(double w, double h, int tw, int th, double margin_px) {
  if (!(w > 0) || !(h > 0)) return Affine2::identity();
  const double aw = std::max(1.0, tw - 2 * margin_px), ah = std::max(1.0, th - 2 * margin_px);
  const double s = std::min(aw / w, ah / h);
  return Affine2::translate((tw - w * s) / 2, (th - h * s) / 2) * Affine2::scale(s, s);
}

Result<Image> render_character(const Character& ch, const CharacterMesh& mesh,
                               const RenderOptions& o, std::span<const Points> positions) {
  int w = o.width > 0 ? o.width : static_cast<int>(std::ceil(ch.width));
  int h = o.height > 0 ? o.height : static_cast<int>(std::ceil(ch.height));
  w = std::clamp(w, 1, 8192);
  h = std::clamp(h, 1, 8192);
  const int ss = std::clamp(o.supersample, 1, 4);
  auto canvas = Canvas::offscreen(w * ss, h * ss);
  if (!canvas.ok()) return Result<Image>::failure(canvas.error);
  Canvas& c = **canvas.value;
  c.set_antialias(o.antialias);
  c.clear(o.background);
  DrawList list;
  build_draw_list(ch, mesh, positions, fit_view(ch.width, ch.height, w * ss, h * ss),
                  o.tolerance_px * ss, list);
  if (std::string err = c.draw(list); !err.empty()) return Result<Image>::failure(err);
  const std::vector<std::uint8_t> px = c.read_premultiplied();
  return Result<Image>::success(downsample_premultiplied(px.data(), w, h, ss));
}

}  // namespace mar
