// After warm-up a live frame allocates nothing — with every simulated device feeding the
// decoders, mapping with filters, soft takeover and rotation, solving and rendering.
#include "alloc_counter.h"
#include "app/alloc_count.h"
#include "app/live.h"
#include "loop/hud_show.h"
#include "test_util.h"

#include <SDL.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <csignal>
#include <fstream>
#include <thread>

namespace mar {
namespace {

// Loads a show headless at 120 Hz, runs 30 warm-up frames, then 570 frames that must not
// allocate (counted by the test's operator new and by the show itself).
std::unique_ptr<LiveShow> run_steady(const std::string& path) {
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  o.warmup = 30;
  auto s = LiveShow::load(path, o);
  EXPECT_TRUE(s.ok()) << s.error;
  if (!s.ok()) return nullptr;
  LiveShow& show = **s.value;
  for (int f = 0; f < 30; ++f) show.frame(int64_t(f * 1e9 / 120));
  const long before = test::allocation_count();
  for (int f = 30; f < 600; ++f) show.frame(int64_t(f * 1e9 / 120));
  EXPECT_EQ(test::allocation_count() - before, 0);
  EXPECT_EQ(show.allocations_after_warmup(), 0u);
  return std::move(*s.value);
}

TEST(LiveAlloc, SteadyFramesAllocateNothing) {
  set_allocation_counter(&heap_allocation_count);
  const std::string path = (test::source_dir() / "tests/data/shows/every_sim_looping.toml").string();
  const std::unique_ptr<LiveShow> s = run_steady(path);
  ASSERT_TRUE(s);
  LiveShow& show = *s;
  EXPECT_GT(show.mapping().stats().matched, 500u);  // the devices really drove it
}

// Pen grabs and releases (taking over a handle, and a new handle away from the handles:
// a rank-2 update of the factorisation) allocate nothing either, and re-factorise nothing.
TEST(LiveAlloc, PenGrabsAndReleasesAllocateNothing) {
  set_allocation_counter(&heap_allocation_count);
  const std::string path = (test::source_dir() / "tests/data/shows/pen_grab_looping.toml").string();
  const std::unique_ptr<LiveShow> s = run_steady(path);
  ASSERT_TRUE(s);
  LiveShow& show = *s;
  const auto j = nlohmann::json::parse(show.stats_json());
  EXPECT_GE(j["grabs"]["count"].get<int>(), 16);  // 4 strokes down and up per 1.2 s loop... at least 4 loops
  EXPECT_EQ(j["refactorizations"]["count"], 0);
}

// The attract loop starting (its mapping reset to the show's as loaded, its script rewound),
// playing and handing over allocates nothing either.
TEST(LiveAlloc, TheAttractLoopStartingAndHandingOverAllocatesNothing) {
  set_allocation_counter(&heap_allocation_count);
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  o.warmup = 30;
  auto s = LiveShow::load((test::source_dir() / "tests/data/shows/attract.toml").string(), o);
  ASSERT_TRUE(s.ok()) << s.error;
  LiveShow& show = **s.value;
  for (int f = 0; f < 30; ++f) show.frame(int64_t(f * 1e9 / 60));
  const long before = test::allocation_count();
  for (int f = 30; f < 660; ++f) show.frame(int64_t(f * 1e9 / 60));  // starts at 2.6 s, hands over at 9 s
  EXPECT_EQ(test::allocation_count() - before, 0);
  EXPECT_EQ(show.allocations_after_warmup(), 0u);
  ASSERT_NE(show.attract(), nullptr);
  EXPECT_EQ(show.attract()->starts(), 1u);
  EXPECT_EQ(show.attract()->handovers(), 1u);
}

// The HUD allocates nothing once its glyphs are made: a frame's lines are formatted into fixed
// buffers and drawn as copies from the glyph texture. Drawn here on SDL's software renderer
// on a surface (a window's present, which goes through the window system, is counted apart).
TEST(LiveAlloc, TheHudAllocatesNothing) {
  test::HudShow hs;
  const ShowConfig& show = hs.show;
  Mapping& m = hs.m;
  SDL_Surface* surface = SDL_CreateRGBSurfaceWithFormat(0, 640, 360, 32, SDL_PIXELFORMAT_ABGR8888);
  SDL_Renderer* r = SDL_CreateSoftwareRenderer(surface);
  Hud hud(show);
  ASSERT_EQ(hud.load_font(r), "");
  Event e;
  e.kind = ControlKind::MidiCC;
  e.number = 7;
  e.hi = 127;
  const DeviceState states[] = {DeviceState::Connected};
  auto frame = [&](int f) {
    e.value = f % 128;
    m.apply(e);
    const Event last[] = {e};
    hud.draw(r, 640, 360, HudFrame{1000.0 + f, 16667, 8, 8, 0.01 * f, states, last}, m);
    SDL_RenderFlush(r);
  };
  for (int f = 0; f < 10; ++f) frame(f);
  const long before = test::allocation_count();
  for (int f = 10; f < 200; ++f) frame(f);
  EXPECT_EQ(test::allocation_count() - before, 0);
  EXPECT_GE(hud.line_count(), 3u);
  SDL_DestroyRenderer(r);
  SDL_FreeSurface(surface);
}

// An edit saved again while the first is still being prepared: the newest is prepared in its
// place, between frames. Giving one preparation up and starting the next allocates (a thread,
// its job, the show's options), and that is the reload's, not a frame's (found on a busy CI
// machine: 8 allocations after warm-up, where preparing was slow enough to see the second save).
TEST(LiveAlloc, AnEditSavedAgainWhileBeingPreparedIsTheReloadsAllocationNotAFrames) {
  set_allocation_counter(&heap_allocation_count);
  const auto dir = test::temp_dir("alloc-reload-again");
  const std::string path = (dir / "show.toml").string(), heavy = (dir / "crowd.svg").string(),
                    crowd_rig = (dir / "crowd.toml").string();
  const std::string rig = (test::source_dir() / "config/rigs/figure.toml").string();
  const std::string rest = "rate = 60\n[display]\nwidth = 160\nheight = 200\n"
                           "[[device]]\nname = \"k\"\nsim = \"nanokontrol2\"\nscript = \"0 move knob1 0\"\n";
  std::ofstream(path) << "[show]\nrig = \"" << rig << "\"\n" << rest;
  {  // a drawing slow to prepare (a tenth of a second and more): the second request comes while it is
    std::ofstream svg(heavy);
    svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"1600\" height=\"1600\">";
    for (int k = 0; k < 300; ++k)
      svg << "<ellipse cx=\"" << 20 + 40 * (k % 40) << "\" cy=\"" << 20 + 40 * (k / 40) << "\" rx=\"15\" ry=\"12\" fill=\"#a53\"/>";
    svg << "</svg>";
    std::ofstream(crowd_rig) << "character = \"crowd.svg\"\n[[handle]]\nname = \"a\"\nrest = [20.0, 20.0]\n"
                                "[[handle]]\nname = \"b\"\nrest = [1580.0, 1580.0]\n";
  }
  RunOptions o;
  o.headless = true;
  o.realtime = true;
  o.quiet = true;
  o.warmup = 30;
  o.frames = 1'000'000;
  auto loaded = LiveShow::load(path, o);
  ASSERT_TRUE(loaded.ok()) << loaded.error;
  LiveShow& show = **loaded.value;
  std::atomic<bool> finished{false};
  std::thread editor([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(800));  // past warm-up
    std::ofstream(path + ".tmp") << "[show]\nrig = \"" << crowd_rig << "\"\n" << rest;
    std::filesystem::rename(path + ".tmp", path);
    std::raise(SIGHUP);
    std::this_thread::sleep_for(std::chrono::milliseconds(40));
    std::raise(SIGHUP);  // again, while the first is prepared
    for (int k = 0; k < 600 && !finished; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (!finished) show.stop();
  });
  EXPECT_EQ(show.run(), 0);
  finished = true;
  editor.join();
  ASSERT_TRUE(show.reload_asked());
  EXPECT_GT(show.frames(), 40);
  EXPECT_EQ(show.allocations_after_warmup(), 0u);
  auto prepared = show.take_prepared();
  ASSERT_TRUE(prepared.ok()) << prepared.error;
}

}  // namespace
}  // namespace mar
