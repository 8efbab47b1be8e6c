// End-to-end: scripted performances through simulated devices, the real decoders, the
// mapping, the solver and the renderer (headless). The window and the canvas:
// test_live_window.cpp; the shipped shows, their clocks and run_hash: test_live_shows.cpp.
#include "app/keys.h"
#include "app/live.h"
#include "render/image.h"
#include "live_util.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

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

TEST(Live, FaderSweepMovesAHandleFromAToB) {
  const auto path = show_file("fader.toml", R"(
[[device]]
name = "korg"
sim = "nanokontrol2"
script = """
0.0 move fader4 0
0.2 move fader4 1 over 1.0
"""
[[binding]]
device = "korg"
control = "cc 3"
target = "handle.chest.x"
range = [150.0, 190.0]
)");
  auto s = load(path);
  ASSERT_TRUE(s);
  const int h = s->mapping().handle_index("chest");
  ASSERT_GE(h, 0);
  std::vector<double> xs;
  for (int f = 0; f < 120; ++f) {
    s->frame(int64_t(f * 1e9 / 60));
    xs.push_back(s->mapping().targets()[size_t(h)].x());
  }
  EXPECT_NEAR(xs[5], 150.0, 1e-9);        // before the move: A
  EXPECT_NEAR(xs.back(), 190.0, 1e-9);    // CC 127: exactly B
  for (size_t i = 1; i < xs.size(); ++i) EXPECT_GE(xs[i], xs[i - 1] - 1e-12);  // monotone
  EXPECT_NEAR(xs[42], 150.0 + 40.0 * std::round((42 / 60.0 - 0.2) * 127) / 127, 0.35);  // mid-sweep
  // The solved character follows: the handle's point ends within 0.5% of the diagonal.
  const Vec2 p = handle_position(*s, h);
  EXPECT_NEAR(p.x(), 190.0, 0.005 * 516);
  EXPECT_NEAR(p.y(), 190.0, 0.005 * 516);
}

// A pad pressed softly, then pressed harder and the channel pressure raised, all from a
// script: a simulated controller sends what a real one's pads send (note-on velocity,
// polyphonic key pressure, channel pressure), and a binding names the pad as the profile does.
TEST(Live, APadsVelocityAndPressureDriveTargetsByTheProfilesName) {
  const auto path = show_file("pad_velocity.toml", R"(
[[device]]
name = "apc"
type = "sim"
profile = "apc_mini_mk2"
script = """
0.1 press pad_r1c1 for 0.6 velocity 64
0.2 pressure pad_r1c1 1 over 0.2
0.3 aftertouch 0.5
"""
[[binding]]
device = "apc"
control = "pad_r1c1 velocity"
target = "handle.chest.x"
range = [100.0, 227.0]
[[binding]]
device = "apc"
control = "pad_r1c1 pressure"
target = "handle.chest.y"
range = [0.0, 127.0]
takeover = false
[[binding]]
device = "apc"
control = "aftertouch"
target = "handle.head.x"
range = [0.0, 127.0]
takeover = false
)");
  auto s = load(path);
  ASSERT_TRUE(s);
  const size_t h = size_t(s->mapping().handle_index("chest")), head = size_t(s->mapping().handle_index("head"));
  auto at = [&](double t) {
    for (long f = s->frames(); double(f) / 60 <= t; f = s->frames()) s->frame(int64_t(double(f) * 1e9 / 60));
    return s->mapping().targets();
  };
  EXPECT_NEAR(at(0.15)[h].x(), 164.0, 1e-9) << "velocity 64 of 127";
  EXPECT_NEAR(at(0.5)[h].y(), 127.0, 1e-9) << "full pressure";
  EXPECT_NEAR(at(0.5)[head].x(), 64.0, 1e-9) << "channel pressure 0.5 is 64";
}

TEST(Live, EncoderWithBounceRotatesByTheConfiguredAngle) {
  const auto path = show_file("encoder.toml", R"(
[[device]]
name = "knobs"
sim = "knob_box"
bounce_ms = 3.0
seed = 9
script = """
0.1 turn 1 24 over 2.0
2.5 turn 1 -6 over 0.5
"""
[[group]]
name = "arm"
handles = ["right-hand"]
pivot = [200.0, 170.0]

[[binding]]
device = "knobs"
control = "encoder 1"
target = "rotate.arm"
mode = "delta"
step = 2.5
)");
  auto s = load(path);
  ASSERT_TRUE(s);
  for (int f = 0; f < 140; ++f) s->frame(int64_t(f * 1e9 / 60));
  EXPECT_DOUBLE_EQ(s->mapping().angle(0), 60.0);  // 24 detents x 2.5 degrees
  for (int f = 140; f < 200; ++f) s->frame(int64_t(f * 1e9 / 60));
  EXPECT_DOUBLE_EQ(s->mapping().angle(0), 45.0);  // then 6 back
  // The target is the rest position rotated 45 degrees about the pivot.
  const Vec2 r = Vec2(245, 250) - Vec2(200, 170);
  const double c = std::cos(M_PI / 4), sn = std::sin(M_PI / 4);
  const Vec2 want = Vec2(200, 170) + Vec2(c * r.x() - sn * r.y(), sn * r.x() + c * r.y());
  const int h = s->mapping().handle_index("right-hand");
  EXPECT_NEAR((s->mapping().targets()[size_t(h)] - want).norm(), 0, 1e-9);
}

TEST(Live, SoftTakeoverWaitsForTheFaderToCrossAndPosesRecall) {
  const auto path = show_file("takeover.toml", R"(
[[device]]
name = "korg"
sim = "nanokontrol2"
script = """
0.0 move fader1 0.8
0.1 move fader1 0.9 over 0.2
0.5 move fader1 0.1 over 0.5
1.2 press solo1 for 0.1
"""
[[pose]]
name = "up"
handles = { left-hand = [40.0, 100.0] }

[[binding]]
device = "korg"
control = "cc 0"
target = "handle.left-hand.y"
range = [300.0, 100.0]

[[binding]]
device = "korg"
control = "cc 32"
target = "pose.up"
)");
  auto s = load(path);
  ASSERT_TRUE(s);
  const int h = s->mapping().handle_index("left-hand");
  for (int f = 0; f < 24; ++f) s->frame(int64_t(f * 1e9 / 60));
  // Fader at 0.8-0.9 while the hand rests at y = 250 (0.25 of the range): no jump.
  EXPECT_DOUBLE_EQ(s->mapping().goal(h).y(), 250.0);
  for (int f = 24; f < 66; ++f) s->frame(int64_t(f * 1e9 / 60));
  // Moving down through 0.25 picked it up; at 0.1 the hand is at 300 - 0.1 * 200 = 280.
  EXPECT_NEAR(s->mapping().goal(h).y(), 300.0 - 200.0 * 13 / 127.0, 1e-9);
  for (int f = 66; f < 90; ++f) s->frame(int64_t(f * 1e9 / 60));
  EXPECT_EQ(s->mapping().goal(h), Vec2(40.0, 100.0));
}

TEST(Live, PenGrabDragsTheNearestPoint) {
  const auto path = show_file("grab.toml", R"(
[[device]]
name = "pen"
sim = "pen_tablet"
script = """
0.1 stroke 0.3333,0.5119 0.2,0.4 over 0.5 pressure 0.8   # the left elbow, up and out
"""
[[binding]]
device = "pen"
control = "pointer"
target = "grab"
area = [0.0, 0.0, 300.0, 420.0]
)");
  auto s = load(path);
  ASSERT_TRUE(s);
  // Points of the character within 12 units of the point nearest the pen's (100, 215).
  Vec2 g0(0, 0);
  for (const Points& sh : s->puppet().shapes)
    for (const Vec2& v : sh)
      if ((v - Vec2(100, 215)).norm() < (g0 - Vec2(100, 215)).norm()) g0 = v;
  std::vector<std::pair<size_t, size_t>> near;
  for (size_t a = 0; a < s->puppet().shapes.size(); ++a)
    for (size_t k = 0; k < s->puppet().shapes[a].size(); ++k)
      if ((s->puppet().shapes[a][k] - g0).norm() < 12) near.push_back({a, k});
  ASSERT_FALSE(near.empty());
  auto torso_x = [&] {  // mean distance of those points from (60, 168), where the pen goes
    double d = 0;
    for (auto [a, k] : near) d += (s->puppet().shapes[a][k] - Vec2(60, 168)).norm();
    return d / double(near.size());
  };
  const double rest_x = torso_x();
  double dragged_x = 0;
  for (int f = 0; f < 50; ++f) {
    s->frame(int64_t(f * 1e9 / 60));
    if (f == 34) {
      EXPECT_TRUE(s->mapping().grab_active());
      dragged_x = torso_x();
    }
  }
  EXPECT_FALSE(s->mapping().grab_active());  // pen lifted at 0.6 s
  nlohmann::json j = nlohmann::json::parse(s->stats_json());
  EXPECT_EQ(j["grabs"]["count"], 2);             // pen down, pen up: rank-2 updates
  EXPECT_EQ(j["refactorizations"]["count"], 0);  // no re-factorisation for a grab
  // While held, the elbow followed the pen: much closer to where the pen went.
  EXPECT_LT(dragged_x, 0.5 * rest_x) << rest_x;
}

TEST(Live, RecordAndReplayGiveTheSameRunHash) {
  const auto dir = test::temp_dir("replay");
  const std::string show = (test::source_dir() / "config/shows/demo.toml").string();
  const std::string rec = (dir / "demo.rec").string();
  auto live = test::run_cli("run " + show + " --headless --frames 240 --record " + rec + " --stats " +
                            (dir / "live.json").string());
  ASSERT_EQ(live.exit_code, 0) << live.err;
  auto rep = test::run_cli("replay " + rec + " --show " + show + " --stats " + (dir / "replay.json").string());
  ASSERT_EQ(rep.exit_code, 0) << rep.err;
  std::ifstream a(dir / "live.json"), b(dir / "replay.json");
  const auto ja = nlohmann::json::parse(a), jb = nlohmann::json::parse(b);
  EXPECT_EQ(ja["frames"], 240);
  EXPECT_EQ(jb["frames"], 240);
  EXPECT_EQ(ja["run_hash"], jb["run_hash"]);
  EXPECT_EQ(ja["events"]["mapped"], jb["events"]["mapped"]);
  // A different performance gives a different hash.
  auto other = test::run_cli("run " + show + " --headless --frames 120 --stats " + (dir / "short.json").string());
  std::ifstream c(dir / "short.json");
  EXPECT_NE(nlohmann::json::parse(c)["run_hash"], ja["run_hash"]);
}

TEST(Live, StatsJsonHasEveryField) {
  const auto dir = test::temp_dir("stats");
  auto r = test::run_cli("run " + (test::source_dir() / "config/shows/demo.toml").string() +
                         " --headless --frames 90 --stats " + (dir / "s.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream f(dir / "s.json");
  const auto j = nlohmann::json::parse(f);
  EXPECT_EQ(j["frames"], 90);
  for (const char* st : {"inputs", "map", "poses", "motion", "solve", "render", "present", "frame"})
    for (const char* q : {"p50", "p99", "max"}) {
      EXPECT_GE(j["stages_us"][st][q].get<double>(), 0.0) << st << q;
    }
  EXPECT_TRUE(j.contains("overruns"));
  EXPECT_GE(j["iterations"]["min"].get<int>(), 3);
  EXPECT_GT(j["latency_us"]["events"].get<int>(), 0);
  EXPECT_GT(j["latency_us"]["p99"].get<double>(), 0.0);
  EXPECT_EQ(j["heap_allocations_after_warmup"], 0);
  EXPECT_EQ(j["run_hash"].get<std::string>().size(), 16u);
}

TEST(Live, BadShowFilesExit2WithFileAndLine) {
  const auto bad = show_file("bad.toml", R"(
[[device]]
name = "korg"
sim = "nanokontrol2"

[[binding]]
device = "korg"
control = "cc 300"
target = "handle.head.x"
)");
  auto r = test::run_cli("run " + bad + " --headless --frames 5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad.toml:16"), std::string::npos) << r.err;
  const auto bad_target = show_file("bad_target.toml", "[[device]]\nname = \"k\"\nsim = \"nanokontrol2\"\n"
                                                       "[[binding]]\ndevice = \"k\"\ncontrol = \"cc 1\"\ntarget = \"handle.nose\"\n");
  r = test::run_cli("run " + bad_target + " --headless --frames 5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad_target.toml:15: the rig has no handle 'nose'"), std::string::npos) << r.err;
  const auto bad_script = show_file("bad_script.toml", "[[device]]\nname = \"k\"\nsim = \"nanokontrol2\"\n"
                                                       "script = \"0 move fader1 0.5\\n1 move fader12 1\"\n");
  r = test::run_cli("run " + bad_script + " --headless --frames 5");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad_script.toml:9: device 'k' script line 2"), std::string::npos) << r.err;
  const auto syntax = test::write_temp("syntax.toml", "[show]\nrig = \n");
  r = test::run_cli("run " + syntax + " --headless");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("syntax.toml:2"), std::string::npos) << r.err;
}

TEST(Live, LearnBindsTheNextControlThatMovesAndWritesIt) {
  const auto path = show_file("learn.toml", R"(
[[device]]
name = "korg"
sim = "nanokontrol2"
script = """
0.5 move knob3 0.7 over 0.3
"""
)");
  auto r = test::run_cli("run " + path + " --headless --learn handle.head.x");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("learned: korg 'cc 18 ch 1' -> handle.head.x"), std::string::npos) << r.out;
  std::ifstream f(path);
  const std::string text((std::istreambuf_iterator<char>(f)), {});
  EXPECT_NE(text.find("control = \"cc 18 ch 1\"\ntarget = \"handle.head.x\""), std::string::npos) << text;
  // The learned binding now drives the head.
  auto s = load(path);
  ASSERT_TRUE(s);
  for (int f2 = 0; f2 < 60; ++f2) s->frame(int64_t(f2 * 1e9 / 60));
  EXPECT_NE(s->mapping().goal(s->mapping().handle_index("head")).x(), 150.0);
}

}  // namespace
}  // namespace mar
