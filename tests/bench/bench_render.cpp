// What a frame's picture costs, for every example character at 640x720, 1920x1080 and
// 3840x2160: the anti-aliased rasterizer (the canvas every mode draws), SDL's aliased software
// triangles (what it replaced), a window's frame through OpenGL (Mesa's llvmpipe under Xvfb when
// there is a display; llvmpipe is itself a CPU rasterizer on every core): drawn by the GPU with
// fringes, and drawn by the rasterizer then uploaded, and, as the anchor, librsvg rendering
// the same SVG at the same size with cairo (linked into this benchmark only). Each is the median
// of repetitions; a table of medians and ratios follows the usual output. Also the draw-list
// rebuild and the one-time mesh preparation.
#include "character/load.h"
#include "median_reporter.h"
#include "render/canvas.h"

#include <SDL2/SDL.h>
#include <benchmark/benchmark.h>
#include <cairo.h>
#include <librsvg/rsvg.h>

#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

const char* kNames[] = {"figure", "butterfly", "koi", "singer", "candle", "boy", "boy.png"};
constexpr int kCharacters = 7;
const int kSizes[][2] = {{640, 720}, {1920, 1080}, {3840, 2160}};

std::string path_of(int i) {
  const std::string n = kNames[i];
  return std::string(MARIONETTE_SOURCE_DIR) + "/config/characters/" + (n.find('.') == std::string::npos ? n + ".svg" : n);
}

mar::Character load(int i) {
  auto r = mar::load_character(path_of(i));
  if (!r.ok()) std::abort();
  return *r.value;
}

std::string label(const benchmark::State& st) {
  return std::string(kNames[st.range(0)]) + " " + std::to_string(kSizes[st.range(1)][0]) + "x" + std::to_string(kSizes[st.range(1)][1]);
}

void frame(benchmark::State& st, bool antialias) {
  const mar::Character ch = load(int(st.range(0)));
  const mar::CharacterMesh mesh = mar::prepare_mesh(ch);
  const int w = kSizes[st.range(1)][0], h = kSizes[st.range(1)][1];
  auto canvas = mar::Canvas::offscreen(w, h);
  mar::Canvas& c = **canvas.value;
  c.set_antialias(antialias);
  mar::DrawList list;
  const mar::Affine2 view = mar::fit_view(ch.width, ch.height, w, h, 16);
  for (auto _ : st) {
    c.clear(mar::Rgba{0.96f, 0.95f, 0.92f, 1});
    list.clear();
    mar::build_draw_list(ch, mesh, {}, view, 0.3, list);
    c.draw(list);
    benchmark::DoNotOptimize(c.pixels().px);
  }
  st.SetLabel(label(st));
}

void BM_frame_aa(benchmark::State& st) { frame(st, true); }
void BM_frame_aliased(benchmark::State& st) { frame(st, false); }

// A window's frame through OpenGL, presented: the GPU draws the canvas (fringed triangles), or
// (upload) the rasterizer draws it and the GPU only takes the pixels.
void gl_window(benchmark::State& st, bool gpu) {
  const char* d = std::getenv("DISPLAY");
  if (!d || !*d) {
    st.SkipWithError("no display (run under xvfb-run)");
    return;
  }
  SDL_SetHint(SDL_HINT_RENDER_DRIVER, "opengl");
  SDL_SetHint(SDL_HINT_RENDER_VSYNC, "0");
  const mar::Character ch = load(int(st.range(0)));
  const mar::CharacterMesh mesh = mar::prepare_mesh(ch);
  const int w = kSizes[st.range(1)][0], h = kSizes[st.range(1)][1];
  mar::WindowOptions wo;
  wo.width = 640;
  wo.height = 360;
  wo.gpu = gpu;
  auto win = mar::Canvas::window(wo, w, h);
  if (!win.ok()) {
    st.SkipWithError(win.error.c_str());
    return;
  }
  mar::Canvas& c = **win.value;
  if (c.renderer_name() != "opengl") {
    st.SkipWithError(("renderer is " + c.renderer_name()).c_str());
    return;
  }
  mar::DrawList list;
  const mar::Affine2 view = mar::fit_view(ch.width, ch.height, w, h, 16);
  for (auto _ : st) {
    SDL_PumpEvents();
    c.clear(mar::Rgba{0.96f, 0.95f, 0.92f, 1});
    list.clear();
    list.fringe = c.wants_fringe();
    mar::build_draw_list(ch, mesh, {}, view, 0.3, list);
    c.draw(list);
    c.present();
  }
  st.SetLabel(label(st) + " (" + c.renderer_name() + (c.gpu() ? ", drawn by the GPU)" : ", uploaded)"));
}
void BM_frame_gl_window(benchmark::State& st) { gl_window(st, true); }
void BM_frame_gl_upload(benchmark::State& st) { gl_window(st, false); }

// librsvg (cairo) drawing `handle` into a w x h ARGB surface over `background` each iteration,
// the document placed as the canvas places it (fit_view, the same margin); the handle is released.
void librsvg_frames(benchmark::State& st, RsvgHandle* handle, double doc_w, double doc_h, int w, int h, const mar::Rgba& background) {
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, w, h);
  const mar::Affine2 view = mar::fit_view(doc_w, doc_h, w, h, 16);
  const mar::Vec2 o = view.apply(mar::Vec2(0, 0)), e = view.apply(mar::Vec2(doc_w, doc_h));
  const RsvgRectangle viewport{o.x(), o.y(), e.x() - o.x(), e.y() - o.y()};
  for (auto _ : st) {
    cairo_t* cr = cairo_create(surface);
    cairo_set_source_rgb(cr, background.r, background.g, background.b);
    cairo_paint(cr);
    rsvg_handle_render_document(handle, cr, &viewport, nullptr);
    cairo_destroy(cr);
    cairo_surface_flush(surface);
    benchmark::DoNotOptimize(cairo_image_surface_get_data(surface));
  }
  cairo_surface_destroy(surface);
  g_object_unref(handle);
}

// librsvg (cairo) rendering the same SVG at the same size, into an ARGB surface: the anchor.
void BM_frame_librsvg(benchmark::State& st) {
  const std::string path = path_of(int(st.range(0)));
  if (path.ends_with(".png")) {
    st.SkipWithError("not an SVG");
    return;
  }
  GError* err = nullptr;
  RsvgHandle* handle = rsvg_handle_new_from_file(path.c_str(), &err);
  if (!handle) {
    st.SkipWithError(err ? err->message : "librsvg cannot read it");
    return;
  }
  const mar::Character ch = load(int(st.range(0)));
  // (the character's document fitted as the canvas fits it: the same margin)
  librsvg_frames(st, handle, ch.width, ch.height, kSizes[st.range(1)][0], kSizes[st.range(1)][1], mar::Rgba{0.96f, 0.95f, 0.92f, 1});
  st.SetLabel(label(st));
}

void sizes(benchmark::internal::Benchmark* b) {
  for (int c = 0; c < kCharacters; ++c)
    for (int s = 0; s < 3; ++s) b->Args({c, s});
  b->Unit(benchmark::kMicrosecond)->Repetitions(5)->ReportAggregatesOnly(true)->MinTime(0.1);
}
BENCHMARK(BM_frame_aa)->Apply(sizes);
BENCHMARK(BM_frame_aliased)->Apply(sizes);
BENCHMARK(BM_frame_gl_window)->Apply(sizes);
BENCHMARK(BM_frame_gl_upload)->Apply(sizes);
BENCHMARK(BM_frame_librsvg)->Apply(sizes);

void BM_build_draw_list(benchmark::State& st) {
  const mar::Character ch = load(static_cast<int>(st.range(0)));
  const mar::CharacterMesh mesh = mar::prepare_mesh(ch);
  mar::DrawList list;
  for (auto _ : st) {
    list.clear();
    mar::build_draw_list(ch, mesh, {}, mar::fit_view(ch.width, ch.height, 1920, 1080), 0.3, list);
    benchmark::DoNotOptimize(list.indices.data());
  }
  st.SetLabel(kNames[st.range(0)]);
  st.counters["triangles"] = static_cast<double>(list.indices.size() / 3);
}
BENCHMARK(BM_build_draw_list)->DenseRange(0, kCharacters - 1)->Unit(benchmark::kMicrosecond);

// Real clip art from Debian's openclipart-svg at 1920x1080 (curves flattened against it), our
// rasterizer beside librsvg in the same run: a flat drawing, an icon of layered gradients, a
// telephone of gradients, masks and group opacity, a drawing with a blurred drop shadow, a
// pattern. Skipped where the package is not installed.
const char* kClipart[] = {"animals/mammals/skoynk_peterm_.svg", "computer/icons/gnome-mime-application-x-deb.svg",
                          "office/telephone/mobile_phone_01.svg", "computer/icons/etiquette-theme/devices/gnome-dev-cdrom.svg",
                          "special/patterns/pattern-crosses-1.svg"};
constexpr int kClipartW = 1920, kClipartH = 1080;

std::string clipart_path(const benchmark::State& st) { return std::string("/usr/share/openclipart/svg/") + kClipart[st.range(0)]; }

void BM_frame_clipart(benchmark::State& st) {
  mar::LoadOptions lo;
  lo.pixels_per_unit = [](double w, double h) { return mar::fit_view(w, h, kClipartW, kClipartH, 16).max_scale(); };
  auto ch = mar::load_character(clipart_path(st), lo);
  if (!ch.ok()) {
    st.SkipWithError("openclipart-svg is not installed (apt-get install openclipart-svg)");
    return;
  }
  const mar::CharacterMesh mesh = mar::prepare_mesh(*ch.value);
  auto canvas = mar::Canvas::offscreen(kClipartW, kClipartH);
  mar::Canvas& c = **canvas.value;
  mar::DrawList list;
  const mar::Affine2 view = mar::fit_view(ch.value->width, ch.value->height, kClipartW, kClipartH, 16);
  for (auto _ : st) {
    c.clear(mar::Rgba{1, 1, 1, 1});
    list.clear();
    mar::build_draw_list(*ch.value, mesh, {}, view, 0.3, list);
    c.draw(list);
    benchmark::DoNotOptimize(c.pixels().px);
  }
  st.SetLabel(kClipart[st.range(0)]);
  st.counters["layers"] = static_cast<double>(list.layers.size());
}

void BM_frame_clipart_librsvg(benchmark::State& st) {
  GError* err = nullptr;
  RsvgHandle* handle = rsvg_handle_new_from_file(clipart_path(st).c_str(), &err);
  auto ch = mar::load_character(clipart_path(st));
  if (!handle || !ch.ok()) {
    st.SkipWithError("openclipart-svg is not installed (apt-get install openclipart-svg)");
    if (handle) g_object_unref(handle);
    return;
  }
  librsvg_frames(st, handle, ch.value->width, ch.value->height, kClipartW, kClipartH, mar::Rgba{1, 1, 1, 1});
  st.SetLabel(kClipart[st.range(0)]);
}
BENCHMARK(BM_frame_clipart)->DenseRange(0, 4)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true)->MinTime(0.1);
BENCHMARK(BM_frame_clipart_librsvg)->DenseRange(0, 4)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true)->MinTime(0.1);

void BM_prepare_mesh(benchmark::State& st) {
  const mar::Character ch = load(static_cast<int>(st.range(0)));
  for (auto _ : st) benchmark::DoNotOptimize(mar::prepare_mesh(ch));
  st.SetLabel(kNames[st.range(0)]);
}
BENCHMARK(BM_prepare_mesh)->DenseRange(0, kCharacters - 1)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  benchmark::ConsoleReporter console;
  bench::Collector collector;
  bench::Tee tee(&console, &collector);
  benchmark::RunSpecifiedBenchmarks(&tee);
  benchmark::Shutdown();
  // Medians side by side, and the ratios the goals are stated in.
  auto med = [&](const char* bm, int c, int s) {
    const std::string key = std::string(bm) + "/" + std::to_string(c) + "/" + std::to_string(s);
    return bench::median_us(collector, key + "/");
  };
  std::printf("\nmedian us per frame            AA    aliased   AA/aliased   GL (GPU)  GL (upload)   librsvg  librsvg/AA\n");
  for (int s = 0; s < 3; ++s)
    for (int c = 0; c < kCharacters; ++c) {
      const double aa = med("BM_frame_aa", c, s), al = med("BM_frame_aliased", c, s);
      const double gl = med("BM_frame_gl_window", c, s), up = med("BM_frame_gl_upload", c, s), rs = med("BM_frame_librsvg", c, s);
      if (aa < 0) continue;
      char g[16] = "-", u[16] = "-", r[16] = "-", rr[16] = "-";
      if (gl > 0) std::snprintf(g, sizeof g, "%.0f", gl);
      if (up > 0) std::snprintf(u, sizeof u, "%.0f", up);
      if (rs > 0) std::snprintf(r, sizeof r, "%.0f", rs);
      if (rs > 0) std::snprintf(rr, sizeof rr, "%.1fx", rs / aa);
      std::printf("%-10s %4dx%-4d %8.0f %9.0f %10.2fx %10s %12s %9s %11s\n", kNames[c], kSizes[s][0], kSizes[s][1], aa, al, aa / al, g, u, r, rr);
    }
  return 0;
}
