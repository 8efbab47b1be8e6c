// End-to-end in a window (Xvfb): the same frame code as headless, the HUD over the canvas and
// never in it, OpenGL drawing the canvas as the rasterizer does, anti-aliasing against
// supersampling, a transparent stage, the canvas size and the letterbox.
#include "app/keys.h"
#include "app/live.h"
#include "render/image.h"
#include "live_util.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <fstream>
#include <iostream>
#include <optional>
#include <thread>

namespace mar {
namespace {

using test::handle_position;
using test::load;
using test::show_file;

// Window mode runs the same frame code: a show played in an Xvfb window, recorded, replays
// headless to the same run_hash.
TEST(Live, WindowRunReplaysHeadlessToTheSameHash) {
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) GTEST_SKIP() << "xvfb-run not installed";
  const auto dir = test::temp_dir("window_run");
  const std::string show = (test::source_dir() / "config/shows/nanokontrol2.toml").string();
  // Leak checking off for this child only: SDL's X11/dbus modules (see test_cli).
  const std::string cmd = "ASAN_OPTIONS=detect_leaks=0 " + test::xvfb_run() + " -s '-screen 0 800x600x24' '" +
                          std::string(MARIONETTE_BINARY) + "' run '" + show + "' --frames 40 --record '" +
                          (dir / "w.rec").string() + "' --stats '" + (dir / "w.json").string() + "' > '" +
                          (dir / "out.txt").string() + "' 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::ifstream out(dir / "out.txt");
  const std::string text((std::istreambuf_iterator<char>(out)), {});
  EXPECT_NE(text.find("in a window"), std::string::npos) << text;
  EXPECT_EQ(text.find("no window"), std::string::npos) << text;
  auto rep = test::run_cli("replay '" + (dir / "w.rec").string() + "' --show '" + show + "' --stats '" +
                           (dir / "r.json").string() + "'");
  ASSERT_EQ(rep.exit_code, 0) << rep.err;
  std::ifstream a(dir / "w.json"), b(dir / "r.json");
  const auto ja = nlohmann::json::parse(a), jb = nlohmann::json::parse(b);
  EXPECT_EQ(ja["frames"], 40);
  EXPECT_EQ(jb["frames"], 40);
  EXPECT_EQ(ja["run_hash"], jb["run_hash"]);
}

// [display] vsync: in a window (SDL's software renderer under Xvfb, which waits for a 60 Hz
// refresh it emulates), present waits for the refresh, the show says so in --stats, and the
// newest input's age is estimated to the photon: at least its age at frame-ready, plus half a
// refresh. Xvfb gives SDL no refresh rate, so it is measured from the presents. Without vsync
// the estimate says why there is none.
TEST(Live, WithVsyncTheStatsEstimateInputToPhoton) {
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) GTEST_SKIP() << "xvfb-run not installed";
  const auto dir = test::temp_dir("vsync");
  std::ifstream base(test::source_dir() / "tests/data/shows/bench_live.toml");
  std::string text((std::istreambuf_iterator<char>(base)), {});
  text.replace(text.find("rate = 120"), 10, "rate = 60");
  text.replace(text.find("../../../config"), 15, (test::source_dir() / "config").string());
  for (bool vsync : {true, false}) {
    SCOPED_TRACE(vsync);
    std::string t = text;
    if (vsync) t.replace(t.find("[display]"), 9, "[display]\nvsync = true");
    const auto show = dir / (vsync ? "vsync.toml" : "free.toml");
    std::ofstream(show) << t;
    const auto stats = dir / (vsync ? "vsync.json" : "free.json");
    const std::string cmd = "SDL_RENDER_DRIVER=software ASAN_OPTIONS=detect_leaks=0 " + test::xvfb_run() + " -s '-screen 0 800x600x24' '" +
                            std::string(MARIONETTE_BINARY) + "' run '" + show.string() + "' --frames 120 --stats '" +
                            stats.string() + "' > '" + (dir / "out.txt").string() + "' 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    std::ifstream in(stats);
    const auto j = nlohmann::json::parse(in)["late_input"];
    EXPECT_EQ(j["display"]["vsync"], vsync) << j.dump();
    const auto& photon = j["newest_input_to_photon_us_estimate"];
    if (!vsync) {
      EXPECT_EQ(photon, "not estimated: no vsync ([display] vsync = true)");
      continue;
    }
    EXPECT_EQ(j["display"]["refresh_from"], "present intervals") << j.dump();
    const double hz = j["display"]["refresh_hz"].get<double>();
    EXPECT_GT(hz, 10) << j.dump();
    EXPECT_LT(hz, 240) << j.dump();
    ASSERT_TRUE(photon.is_object()) << j.dump();
    EXPECT_GE(photon["p50"].get<double>(), j["newest_input_to_ready_us"]["p50"].get<double>() + 0.5e6 / hz - 1) << j.dump();
  }
}

// The window shows the canvas and, over it, the HUD's text; the canvas itself (what dumps and
// outputs use) never has the HUD. For both window renderers, SDL's software one and OpenGL
// (Mesa under Xvfb): below the HUD, the window's pixels equal the canvas's of the same frame.
TEST(Live, TheHudIsInTheWindowNeverInTheCanvas) {
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) GTEST_SKIP() << "xvfb-run not installed";
  for (const std::string driver : {"software", "opengl"}) {
    const auto dir = test::temp_dir("hud_" + driver);
    const std::string cmd = "SDL_RENDER_DRIVER=" + driver + " ASAN_OPTIONS=detect_leaks=0 " + test::xvfb_run() + " -s '-screen 0 1024x768x24' '" +
                            std::string(MARIONETTE_BINARY) + "' run '" + (test::source_dir() / "config/shows/demo.toml").string() +
                            "' --frames 60 --screenshot '" + (dir / "window.png").string() + "' --dump-frames '" + dir.string() +
                            "' --every 59 --stats '" + (dir / "s.json").string() + "' > '" + (dir / "out.txt").string() + "' 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << driver;
    std::ifstream sj(dir / "s.json");
    const auto j = nlohmann::json::parse(sj);
    EXPECT_EQ(j["canvas"]["window_renderer"], driver);
    // A frame with the HUD on and anti-aliasing on allocates nothing (the screenshot, the dumps
    // and the window system's part of presenting are counted apart).
    EXPECT_EQ(j["heap_allocations_after_warmup"], 0) << driver;
    std::cout << driver << ": the window system allocated " << j["window_present_allocations_after_warmup"]
              << " times presenting 30 frames" << std::endl;
    auto win = read_png_image((dir / "window.png").string());
    auto canvas = read_png_image((dir / "frame_000059.png").string());
    ASSERT_TRUE(win.ok() && canvas.ok()) << driver;
    const Image& w = *win.value;
    const Image& c = *canvas.value;
    ASSERT_EQ(w.width, c.width) << "the window opens at the canvas's size";
    ASSERT_EQ(w.height, c.height);
    auto at = [](const Image& im, int x, int y) { return &im.rgba[(size_t(y) * size_t(im.width) + size_t(x)) * 4]; };
    // The HUD's panel (in the corner that covers the least of the character): where the window
    // differs from the canvas, below the budget bar. Dark panel and light glyphs there in the
    // window, the stage's light background in the canvas; everywhere else the window is the canvas.
    int x0 = w.width, y0 = w.height, x1 = -1, y1 = -1;
    for (int y = 22; y < w.height; ++y)
      for (int x = 0; x < w.width; ++x)
        if (std::abs(int(at(w, x, y)[0]) - int(at(c, x, y)[0])) > 40) {
          x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
        }
    ASSERT_GE(x1, 0) << driver << ": the HUD is in the window";
    EXPECT_TRUE(x0 <= 12 || x1 >= w.width - 13) << driver << ": the panel is at a side (" << x0 << ".." << x1 << ")";
    EXPECT_TRUE(y0 <= 24 || y1 >= w.height - 13) << driver << ": at the top or the bottom (" << y0 << ".." << y1 << ")";
    int dark_w = 0, dark_c = 0, light_w = 0, inside = 0;
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x, ++inside) {
        dark_w += at(w, x, y)[0] < 120;
        light_w += at(w, x, y)[0] > 200;
        dark_c += at(c, x, y)[0] < 120;
      }
    EXPECT_GT(dark_w, inside / 2) << driver << ": the HUD panel";
    EXPECT_GT(light_w, 80) << driver << ": the HUD text";
    EXPECT_LT(dark_c, dark_w / 2) << driver << ": no HUD in the canvas";
    // Outside the panel and the bar, the window is the canvas.
    int off = 0, total = 0;
    for (int y = 22; y < w.height; ++y)
      for (int x = 0; x < w.width; ++x) {
        if (x >= x0 && x <= x1 && y >= y0 && y <= y1) continue;
        ++total;
        for (int k = 0; k < 3; ++k) off += std::abs(int(at(w, x, y)[k]) - int(at(c, x, y)[k])) > 2 ? 1 : 0;
      }
    EXPECT_LE(off, total / 1000) << driver << ": " << off << " channels differ of " << total << " pixels";
  }
}

// In a window with OpenGL (Mesa's llvmpipe under Xvfb) the GPU draws the canvas: the renderer
// is the GL one, the canvas is its render target (fringed triangles), and the frames it dumps
// (read back from the GPU) put at least 99% of pixels within 16/255 of the same frames drawn
// headless by the software rasterizer. Queueing the draw list for the GPU allocates nothing.
TEST(Live, TheGpuDrawsTheCanvasAsTheRasterizerDoes) {
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) GTEST_SKIP() << "xvfb-run not installed";
  for (const char* show : {"demo", "nanokontrol2", "pen_tablet", "singer", "raster", "grid"}) {
    const auto dir = test::temp_dir(std::string("gpu_") + show);
    const std::string file = (test::source_dir() / "config/shows" / (std::string(show) + ".toml")).string();
    const std::string cmd = "SDL_RENDER_DRIVER=opengl ASAN_OPTIONS=detect_leaks=0 " + test::xvfb_run() + " -s '-screen 0 1024x768x24' '" +
                            std::string(MARIONETTE_BINARY) + "' run '" + file + "' --frames 121 --dump-frames '" + (dir / "gpu").string() +
                            "' --every 60 --record '" + (dir / "w.rec").string() + "' --stats '" + (dir / "s.json").string() + "' > '" +
                            (dir / "out.txt").string() + "' 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << show;
    std::ifstream sj(dir / "s.json");
    const auto j = nlohmann::json::parse(sj);
    EXPECT_EQ(j["canvas"]["window_renderer"], "opengl") << show;
    EXPECT_EQ(j["canvas"]["drawn_by"], "gpu") << show;
    EXPECT_EQ(j["heap_allocations_after_warmup"], 0) << show;
    // The same poses headless: the window ran on the wall clock (on a busy machine the governor
    // may have dropped iterations); its recording replays them.
    auto r = test::run_cli("replay '" + (dir / "w.rec").string() + "' --show '" + file + "' --dump-frames '" + (dir / "cpu").string() +
                           "' --every 60");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    double worst = 1;
    for (const char* name : {"frame_000060.png", "frame_000120.png"}) {
      auto g = read_png_image((dir / "gpu" / name).string()), c = read_png_image((dir / "cpu" / name).string());
      ASSERT_TRUE(g.ok() && c.ok()) << show << " " << name;
      const ImageDiff d = compare_images(*g.value, *c.value, 16);
      ASSERT_TRUE(d.same_size) << show;
      worst = std::min(worst, 1 - d.differing_share());
    }
    std::cout << show << ": the GPU's frames put " << 100 * worst << "% of pixels within 16/255 of the rasterizer's (worst of 2)" << std::endl;
    EXPECT_GE(worst, 0.99) << show;
  }
}

// Live frames of every show's character, posed as the show poses it: at least 99% of pixels
// within 16/255 of the same frame drawn with `run --supersample 4` (the canvas at 4x,
// box-filtered). The figures are printed for README. The sanitizer build draws two of the
// shows (a vector character and a PNG one): the drawing code is the same for all six.
TEST(Live, AntiAliasedFramesMatchFourTimesSupersampling) {
  std::vector<const char*> shows = {"demo", "nanokontrol2", "pen_tablet", "singer", "raster", "grid"};
  if (test::kSanitized) shows = {"demo", "raster"};
  for (const char* show : shows) {
    const auto dir = test::temp_dir(std::string("aa_") + show);
    const std::string file = (test::source_dir() / "config/shows" / (std::string(show) + ".toml")).string();
    for (const char* ss : {"1", "4"}) {
      auto r = test::run_cli("run '" + file + "' --headless --frames 121 --dump-frames '" + (dir / ss).string() +
                             "' --every 30 --supersample " + ss);
      ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    double worst = 1;
    int worst_max = 0;
    for (int f = 0; f <= 120; f += 30) {
      char name[32];
      std::snprintf(name, sizeof name, "frame_%06d.png", f);
      auto a = read_png_image((dir / "1" / name).string()), b = read_png_image((dir / "4" / name).string());
      ASSERT_TRUE(a.ok() && b.ok()) << show << " " << name;
      const ImageDiff d = compare_images(*a.value, *b.value, 16);
      ASSERT_TRUE(d.same_size);
      worst = std::min(worst, 1 - d.differing_share());
      worst_max = std::max(worst_max, d.max_channel_diff);
    }
    std::cout << show << ": worst of 5 frames " << 100 * worst << "% of pixels within 16/255 of --supersample 4 (max "
              << worst_max << ")" << std::endl;
    EXPECT_GE(worst, 0.99) << show;
  }
}

// background = "transparent": dumps carry alpha; a window drawn with OpenGL on X11 gets an ARGB
// visual and shows the stage with alpha (premultiplied, as compositors and OBS read it); SDL's
// software renderer has none, says so, and shows the stage on chroma green instead.
TEST(Live, ATransparentStageHasAlphaInDumpsAndInAWindowThatCan) {
  const auto dir = test::temp_dir("transparent");
  const auto path = show_file("transparent.toml", "[output]\nwidth = 160\nheight = 200\n") ;
  std::string show;
  {
    std::ifstream in(path);
    show.assign(std::istreambuf_iterator<char>(in), {});
  }
  show.replace(show.find("[display]\n"), 10, "[display]\nbackground = \"transparent\"\nhud = false\n");
  const std::string file = (dir / "t.toml").string();
  std::ofstream(file) << show;
  auto r = test::run_cli("run '" + file + "' --headless --frames 2 --dump-frames '" + (dir / "h").string() + "' --every 1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto dump = read_png_image((dir / "h" / "frame_000001.png").string());
  ASSERT_TRUE(dump.ok());
  auto alpha = [](const Image& im, int x, int y) { return im.rgba[(size_t(y) * size_t(im.width) + size_t(x)) * 4 + 3]; };
  EXPECT_EQ(alpha(*dump.value, 2, 2), 0);
  EXPECT_EQ(alpha(*dump.value, 80, 100), 255);  // the figure's shirt
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) GTEST_SKIP() << "xvfb-run not installed";
  for (const std::string driver : {"opengl", "software"}) {
    const auto shot = dir / (driver + ".png"), err = dir / (driver + ".txt");
    const std::string cmd = "SDL_RENDER_DRIVER=" + driver + " ASAN_OPTIONS=detect_leaks=0 " + test::xvfb_run() + " -s '-screen 0 800x600x24' '" +
                            std::string(MARIONETTE_BINARY) + "' run '" + file + "' --frames 3 --screenshot '" + shot.string() +
                            "' > '" + err.string() + "' 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << driver;
    std::ifstream e(err);
    const std::string said((std::istreambuf_iterator<char>(e)), {});
    auto win = read_png_image(shot.string());
    ASSERT_TRUE(win.ok()) << driver;
    const Image& w = *win.value;
    const uint8_t* corner = &w.rgba[(size_t(2) * size_t(w.width) + 2) * 4];
    EXPECT_EQ(alpha(w, 80, 100), 255) << driver;
    if (driver == "opengl") {
      EXPECT_EQ(said.find("no alpha channel"), std::string::npos) << said;
      EXPECT_EQ(corner[3], 0) << "the window's background is transparent";
    } else {
      EXPECT_NE(said.find("no alpha channel"), std::string::npos) << said;
      EXPECT_EQ(corner[3], 255);
      EXPECT_EQ(corner[0], 0);
      EXPECT_EQ(corner[1], 255) << "chroma green";
      EXPECT_EQ(corner[2], 0);
    }
  }
}

// [output] sets the canvas: dumps have its size whatever the window's, and a window shows it
// scaled to fit, letterboxed.
TEST(Live, OutputSizeIsTheCanvasAndTheWindowLetterboxesIt) {
  const auto dir = test::temp_dir("output_size");
  const auto path = show_file("output.toml", R"(hud = false
[output]
width = 480
height = 270
[[device]]
name = "korg"
sim = "nanokontrol2"
script = "0.0 move fader1 0.5"
[[binding]]
device = "korg"
control = "cc 0"
target = "handle.chest.x"
)");
  auto r = test::run_cli("run '" + path + "' --headless --frames 3 --dump-frames '" + (dir / "h").string() + "' --every 1 --stats '" +
                         (dir / "s.json").string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto img = read_png_image((dir / "h" / "frame_000002.png").string());
  ASSERT_TRUE(img.ok());
  EXPECT_EQ(img.value->width, 480);  // [display] is 160x200: the canvas is [output]'s
  EXPECT_EQ(img.value->height, 270);
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) GTEST_SKIP() << "xvfb-run not installed";
  const std::string cmd = "ASAN_OPTIONS=detect_leaks=0 " + test::xvfb_run() + " -s '-screen 0 800x600x24' '" + std::string(MARIONETTE_BINARY) +
                          "' run '" + path + "' --frames 3 --screenshot '" + (dir / "w.png").string() + "' >/dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  auto win = read_png_image((dir / "w.png").string());
  ASSERT_TRUE(win.ok());
  const Image& w = *win.value;
  ASSERT_EQ(w.width, 160);  // the window is [display]'s size
  ASSERT_EQ(w.height, 200);
  // 480x270 into 160x200: 160x90, centred; black bars of 55 rows above and below.
  auto px = [&](int x, int y) { return &w.rgba[(size_t(y) * size_t(w.width) + size_t(x)) * 4]; };
  for (int x : {0, 80, 159}) {
    EXPECT_EQ(px(x, 10)[0] + px(x, 10)[1] + px(x, 10)[2], 0) << x;
    EXPECT_EQ(px(x, 190)[0] + px(x, 190)[1] + px(x, 190)[2], 0) << x;
    EXPECT_GT(px(x, 100)[0], 100) << x << ": the stage's background";
  }
}

// Scenery behind the character is drawn once and copied under each frame (Canvas::set_underlay):
// on the GPU as a texture. The frames an OpenGL window dumps (read back from the GPU) put at
// least 99 % of pixels within 16/255 of the same frames drawn headless.
// The window runs on the wall clock, so its frame 60 is the show at whatever moment it was drawn
// (on a busy machine, later than the virtual clock's 0.5 s): frame 0 is compared whole, frame 60
// where nothing in the show moves (pixels the same in every headless frame of the knob's loop) —
// the underlay, and the figure but its lifting arm.
TEST(Live, ScenerysUnderlayIsTheSameOnTheGpu) {
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) GTEST_SKIP() << "xvfb-run not installed";
  const std::string show = (test::source_dir() / "tests/data/shows/scenery.toml").string();
  const auto gl = test::temp_dir("underlay_gl"), sw = test::temp_dir("underlay_headless");
  const std::string cmd = "SDL_RENDER_DRIVER=opengl ASAN_OPTIONS=detect_leaks=0 " + test::xvfb_run() + " -s '-screen 0 800x600x24' '" +
                          std::string(MARIONETTE_BINARY) + "' run '" + show + "' --frames 61 --dump-frames '" + gl.string() +
                          "' --every 60 --stats '" + (gl / "s.json").string() + "' > '" + (gl / "out.txt").string() + "' 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::ifstream sj(gl / "s.json");
  const auto j = nlohmann::json::parse(sj);
  if (j["canvas"]["window_renderer"] != "opengl") GTEST_SKIP() << "no OpenGL renderer here";
  // the knob's whole loop (2 s at 120 Hz), every frame
  const std::string head = "'" + std::string(MARIONETTE_BINARY) + "' run '" + show + "' --headless --frames 241 --dump-frames '" +
                           sw.string() + "' --every 1 > /dev/null 2>&1";
  ASSERT_EQ(std::system(head.c_str()), 0);
  auto first = read_png_image((sw / "frame_000000.png").string());
  ASSERT_TRUE(first.ok());
  const Image& rest = *first.value;
  std::vector<char> still(rest.rgba.size() / 4, 1);
  for (int f = 1; f <= 240; ++f) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d.png", f);
    auto img = read_png_image((sw / name).string());
    ASSERT_TRUE(img.ok() && img.value->rgba.size() == rest.rgba.size()) << name;
    for (size_t p = 0; p < still.size(); ++p)
      for (size_t c = 0; c < 4 && still[p]; ++c) still[p] = img.value->rgba[4 * p + c] == rest.rgba[4 * p + c];
  }
  const size_t kept = size_t(std::count(still.begin(), still.end(), 1));
  ASSERT_GT(kept, still.size() * 8 / 10) << "the show's arm moves over a small part of the canvas";
  auto gl0 = read_png_image((gl / "frame_000000.png").string()), gl60 = read_png_image((gl / "frame_000060.png").string());
  ASSERT_TRUE(gl0.ok() && gl60.ok());
  EXPECT_LE(compare_images(*gl0.value, rest, 16).differing_share(), 0.01) << "frame 0, whole";
  ASSERT_EQ(gl60.value->rgba.size(), rest.rgba.size());
  size_t differing = 0;
  for (size_t p = 0; p < still.size(); ++p) {
    if (!still[p]) continue;
    int d = 0;
    for (size_t c = 0; c < 4; ++c) d = std::max(d, std::abs(int(gl60.value->rgba[4 * p + c]) - int(rest.rgba[4 * p + c])));
    differing += d > 16;
  }
  EXPECT_LE(double(differing) / double(kept), 0.01) << "frame 60, where the show does not move";
}

}  // namespace
}  // namespace mar
