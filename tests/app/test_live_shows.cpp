// End-to-end with the shipped shows: their determinism (the demo's pinned run_hash, one
// run_hash idle and loaded), the wall clock and late input, soft takeover's messages, the
// raster, grid, key-pose and singer shows, a SIGHUP reload, the kiosk, every show validating.
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

// A show naming a corpus descriptor still runs where the corpus is absent.
TEST(Live, MissingCorpusDescriptorFallsBackToTheBuiltInOne) {
  const auto dir = test::temp_dir("corpus-fallback");
  const std::string show = (dir / "pen.toml").string();
  {
    std::ofstream f(show);
    f << "[show]\nrig = \"" << (test::source_dir() / "config/rigs/koi.toml").string() << "\"\n"
      << "[[device]]\nname = \"pen\"\nsim = \"pen_tablet\"\n"
      << "descriptor = \"corpus:hid/wacom-hid-descriptors/Huion_H640P/0003_256C_006D.0006.hid.bin\"\n"
      << "script = \"0.1 stroke 0.5,0.5 0.6,0.6 over 0.2 pressure 0.5\"\n"
      << "[[binding]]\ndevice = \"pen\"\ncontrol = \"pointer\"\ntarget = \"grab\"\n";
  }
  ::setenv("MARIONETTE_CORPUS_DIR", "/nonexistent-corpus", 1);
  auto r = test::run_cli("run " + show + " --headless --frames 30");
  ::unsetenv("MARIONETTE_CORPUS_DIR");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("pen.toml:3: device 'pen'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("using the built-in descriptor"), std::string::npos) << r.err;
}

// The demo keeps every part's shape: the per-frame quality figure (worst part's distortion,
// % of the height) stays small over the whole show (headless, so deterministic). Before the
// joints and reach work its median was 3.4%.
TEST(Live, DemoPartsKeepTheirShape) {
  const auto dir = test::temp_dir("quality");
  auto r = test::run_cli("run " + (test::source_dir() / "config/shows/demo.toml").string() + " --headless --stats " +
                         (dir / "s.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream f(dir / "s.json");
  const auto j = nlohmann::json::parse(f);
  const auto& q = j["quality"]["worst_part_distortion"];
  EXPECT_LT(q["p50"].get<double>(), 0.5) << q.dump();
  EXPECT_LT(q["max"].get<double>(), 2.5) << q.dump();
  // where the max was: a part of the figure (the demo's one character), on a frame of the show
  const auto& w = j["quality"]["worst_part"];
  ASSERT_TRUE(w.is_object()) << j["quality"].dump();
  const std::string part = w["part"].get<std::string>();
  std::ifstream svg(test::characters_dir() / "figure.svg");
  const std::string text((std::istreambuf_iterator<char>(svg)), {});
  EXPECT_NE(text.find("id=\"" + part + "\""), std::string::npos) << part;
  EXPECT_GE(w["frame"].get<long>(), 0);
  EXPECT_LT(w["frame"].get<long>(), j["frames"].get<long>());
  EXPECT_EQ(j["grabs"]["count"], 2);
  EXPECT_EQ(j["heap_allocations_after_warmup"], 0);
}

// Determinism safety net (the layout refactor must not change behaviour): the demo's first
// 300 headless frames hash to this constant. A change that moves any vertex changes it —
// update it only when the change is meant to alter the poses, and say so in the commit.
// The shipped demo as it is: on the virtual clock the budget governor stays out of the way (its
// floor is 3 of 8), so the hash is the same on a slow (sanitized or busy) machine. It is the same
// on arm64 too (bash cmake/run.sh arm64): changed for portable_hypot, in the last bit, when
// curves were flattened against the canvas (the figure, drawn 1.6x, gained points on its curves),
// and last when a part sewn to what it hangs from got a second line so it cannot turn about
// the first (the neck; worst part distortion p50 0.42 -> 0.30 %, max 0.80 -> 0.59 %), and when a
// detail that limbs hang from got one too (max 0.591 -> 0.590 %).
TEST(Live, DemoRunHashIsPinned) {
  const auto dir = test::temp_dir("pinned");
  auto r = test::run_cli("run " + (test::source_dir() / "config/shows/demo.toml").string() + " --headless --frames 300 --stats " +
                         (dir / "s.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream f(dir / "s.json");
  EXPECT_EQ(nlohmann::json::parse(f)["run_hash"], "1339e0e095bc10de");
}

nlohmann::json run_demo(const std::string& name, const std::string& extra = "--frames 400") {
  const auto stats = test::temp_dir("demo-runs") / (name + ".json");
  auto r = test::run_cli("run " + (test::source_dir() / "config/shows/demo.toml").string() + " --headless " + extra +
                         " --stats " + stats.string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::ifstream f(stats);
  return r.exit_code == 0 ? nlohmann::json::parse(f) : nlohmann::json();
}

// A headless run is a pure function of the show: with more busy threads than cores, frames
// overrun their budget (measured and reported) but compute exactly what an idle machine does.
// At 1 kHz the budget is tight enough that a loaded machine overruns it (the governor on the
// wall clock would then have dropped iterations, and every frame after would differ).
TEST(Live, DemoGivesOneRunHashIdleAndLoaded) {
  const std::string args = "--frames 400 --rate 1000";
  const auto idle = run_demo("idle", args);
  ASSERT_TRUE(idle.contains("run_hash"));
  EXPECT_EQ(idle["clock"]["mode"], "virtual");
  long overruns = 0;
  {
    test::CpuHog hog;
    for (int k = 0; k < test::repeats(5); ++k) {
      const auto j = run_demo("loaded" + std::to_string(k), args);
      ASSERT_TRUE(j.contains("run_hash"));
      EXPECT_EQ(j["run_hash"], idle["run_hash"]) << "run " << k << " with " << hog.threads() << " busy threads";
      EXPECT_EQ(j["events"]["mapped"], idle["events"]["mapped"]);
      // The iteration count is the show's, whatever the frames cost.
      EXPECT_EQ(j["iterations"]["min"], 8);
      EXPECT_EQ(j["iterations"]["max"], 8);
      EXPECT_EQ(j["clock"]["governor_reductions"], 0);
      overruns += j["overruns"].get<long>();
    }
  }
  std::cout << test::repeats(5) << " loaded runs: " << overruns << " overruns in all, one run_hash " << idle["run_hash"] << std::endl;
}

// --realtime: the wall clock paces the frames (30 frames at 60 Hz take half a second at least),
// the governor acts, and the stats say which clock ran.
TEST(Live, RealtimeFollowsTheWallClockAndSaysSo) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto j = run_demo("realtime", "--realtime --frames 30");
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(j.contains("clock"));
  EXPECT_EQ(j["clock"]["mode"], "realtime");
  EXPECT_EQ(j["frames"], 30);
  EXPECT_GE(s, 29.0 / 60);
}

// Late input: on the wall clock a frame wakes its predicted compute plus a margin before it is
// due and the stats split the latency; on the virtual clock it changes nothing the show computes.
TEST(Live, LateInputOnTheWallClockAndNothingOnTheVirtualClock) {
  const std::string path = (test::source_dir() / "tests/data/shows/bench_live.toml").string();
  auto stats = [&](bool realtime, int late) {
    RunOptions o;
    o.realtime = realtime;
    o.late_input = late;
    o.frames = 150;
    auto s = load(path, o);
    if (!s) return nlohmann::json{};
    EXPECT_EQ(s->run(), 0);
    return nlohmann::json::parse(s->stats_json());
  };
  const auto virtual_on = stats(false, 1), virtual_off = stats(false, 0);
  EXPECT_FALSE(virtual_on.contains("late_input"));
  EXPECT_EQ(virtual_on["run_hash"], virtual_off["run_hash"]);
  for (int late : {0, 1}) {
    const auto j = stats(true, late);
    ASSERT_TRUE(j.contains("late_input")) << j.dump();
    const auto& l = j["late_input"];
    EXPECT_EQ(l["on"], late == 1);
    EXPECT_EQ(l["frames"], 150 - 30);  // after the 30 warm-up frames
    const double period_us = 1e6 / 120;
    EXPECT_LE(l["lead_us"]["max"].get<double>(), period_us);
    if (late) {
      EXPECT_GT(l["lead_us"]["p50"].get<double>(), 0);
    } else {
      EXPECT_EQ(l["lead_us"]["max"].get<double>(), 0);
    }
    EXPECT_GT(l["newest_input_to_shown_us"]["frames"].get<double>(), 100);  // the fader moves every ms
    // A frame is shown at a tick after it read its input, at most a period and its lateness later.
    EXPECT_GE(l["newest_input_to_shown_us"]["p50"].get<double>(), l["device_to_read_us"]["p50"].get<double>());
  }
}

// Soft takeover is said, once per binding still waiting a second after its first wait, with
// where to move the control (the demo's knob, on its way through its target, is not); controls that can
// only jump (a note, a velocity, an OSC value, the clock's phase) set their target at once by
// default, and `takeover` still decides when the show gives it.
TEST(Live, SoftTakeoverIsSaidOnceAndJumpOnlyControlsDoNotWait) {
  const auto path = show_file("takeover.toml", R"(
[[device]]
name = "korg"
sim = "nanokontrol2"
script = """
0.0 move fader1 0
0.1 move fader1 0.1 over 0.3
"""
[[device]]
name = "osc"
type = "osc"
port = 47813
[[binding]]
device = "korg"
control = "cc 0"
target = "handle.chest.x"
range = [100.0, 200.0]
[[binding]]
device = "korg"
control = "note 60 velocity"
target = "handle.head.y"
[[binding]]
device = "osc"
control = "osc /morph"
target = "handle.hips.x"
[[binding]]
device = "korg"
control = "note 61"
target = "handle.hips.y"
takeover = true
)");
  auto r = test::run_cli("run '" + path + "' --headless --frames 120");  // (said after a second of waiting)
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string said = "takeover.toml:21: 'cc 0' -> handle.chest.x waits for soft takeover: move it to 50 % to pick the target up";
  ASSERT_NE(r.err.find(said), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find(said, r.err.find(said) + 1), std::string::npos) << "said once: " << r.err;
  auto s = load(path);
  ASSERT_TRUE(s);
  const Mapping& m = s->mapping();
  ASSERT_EQ(m.binding_count(), 4u);
  EXPECT_TRUE(m.binding(0).tf.takeover);   // a fader: soft takeover
  EXPECT_FALSE(m.binding(1).tf.takeover);  // a velocity jumps
  EXPECT_FALSE(m.binding(2).tf.takeover);  // an OSC value jumps
  EXPECT_TRUE(m.binding(3).tf.takeover);   // the show said so
}

// One control grammar: format_control prints exactly what parse_control reads (what --learn
// writes into a show file is what the show file reader accepts).
TEST(format_control, RoundTripsEveryKind) {
  const char* texts[] = {"cc 7", "cc 7 ch 3", "cc14 5", "nrpn 300", "note 60 ch 10", "pitchbend", "pitchbend ch 2",
                         "note 60 velocity", "note 61 velocity ch 2", "aftertouch", "aftertouch ch 16", "polypressure 64", "beat", "bar",
                         "encoder 2", "button 4", "pointer", "usage x", "usage pressure", "usage button3", "usage 0xFF0001"};
  for (const char* t : texts) {
    ControlSpec a;
    ASSERT_TRUE(parse_control(t, a).ok()) << t;
    EXPECT_EQ(format_control(a), t);
    ControlSpec b;
    ASSERT_TRUE(parse_control(format_control(a), b).ok()) << t;
    EXPECT_EQ(b.kind, a.kind) << t;
    EXPECT_EQ(b.number, a.number) << t;
    EXPECT_EQ(b.channel, a.channel) << t;
  }
}

// The shipped demo uses only what ships: on a clean clone it warns about nothing.
TEST(Live, DemoShowPrintsNoWarning) {
  ::setenv("MARIONETTE_CORPUS_DIR", "/nonexistent-corpus", 1);
  auto r = test::run_cli("run " + (test::source_dir() / "config/shows/demo.toml").string() + " --headless --frames 30");
  ::unsetenv("MARIONETTE_CORPUS_DIR");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("soft takeover"), std::string::npos) << r.err;  // its knob picks its target up on the way
}

// The raster example show: a PNG character, the outline ARAP baseline, a fader, a knob and a
// pen grab; the hand follows the fader and steady frames allocate nothing.
TEST(Live, RasterShowPosesAPngWithTheArapBaseline) {
  const auto dir = test::temp_dir("raster-show");
  auto r = test::run_cli("run " + (test::source_dir() / "config/shows/raster.toml").string() + " --headless --stats " +
                         (dir / "s.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // (a note that a knob waits for soft takeover is the show telling the performer, not a fault)
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("error"), std::string::npos) << r.err;
  std::ifstream f(dir / "s.json");
  const auto j = nlohmann::json::parse(f);
  EXPECT_GT(j["frames"].get<int>(), 200);
  EXPECT_EQ(j["heap_allocations_after_warmup"], 0);
  EXPECT_GE(j["grabs"]["count"].get<int>(), 2);
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  o.frames = 90;  // 1.5 s: the fader has raised the hand
  auto s = LiveShow::load((test::source_dir() / "config/shows/raster.toml").string(), o);
  ASSERT_TRUE(s.ok()) << s.error;
  ASSERT_EQ((*s.value)->run(), 0);
  const Puppet& p = (*s.value)->puppet();
  EXPECT_EQ(p.solver->name(), "arap");
  const int hand = p.rig.find_handle("right-hand");
  ASSERT_GE(hand, 0);
  EXPECT_LT(p.solver->handle_point(size_t(hand)).y(), 130.0);  // from 248 at rest toward 90
}

// The rigid grid in a show, its stiffness turned by knobs: knob 1 sweeps solver.half_width up
// to 6 and back to 1, knob 2 the named region's solver.stiffness.right-arm.
TEST(Live, GridShowTurnsTheStiffnessLive) {
  const auto dir = test::temp_dir("grid-show");
  auto r = test::run_cli("run " + (test::source_dir() / "config/shows/grid.toml").string() + " --headless --stats " +
                         (dir / "s.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // (a note that a knob waits for soft takeover is the show telling the performer, not a fault)
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("error"), std::string::npos) << r.err;
  std::ifstream f(dir / "s.json");
  const auto j = nlohmann::json::parse(f);
  EXPECT_GT(j["frames"].get<int>(), 300);
  EXPECT_EQ(j["heap_allocations_after_warmup"], 0);
  EXPECT_GT(j["refactorizations"]["count"].get<int>(), 5);
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  auto half_width_at = [&](int frames) {
    o.frames = frames;
    auto s = LiveShow::load((test::source_dir() / "config/shows/grid.toml").string(), o);
    EXPECT_TRUE(s.ok()) << s.error;
    if (!s.ok()) return -1.0;
    EXPECT_EQ((*s.value)->run(), 0);
    const Puppet& p = (*s.value)->puppet();
    EXPECT_EQ(p.solver->name(), "rigid_grid");
    return p.solver->parameters()[0].value;
  };
  EXPECT_EQ(half_width_at(60), 3);   // the rig's, until the knob picks it up
  EXPECT_EQ(half_width_at(160), 6);  // knob 1 at the top
  EXPECT_EQ(half_width_at(240), 1);  // and at the bottom
}

// Key poses on knobs: morph.rest.wave takes the figure to its wave key and back; blend.kick and
// blend.wave add up; nothing allocates after warm-up; an unknown key target names the keys.
TEST(Live, KeyShowMorphsAndBlendsTheRigsKeys) {
  const std::string show = (test::source_dir() / "config/shows/keys.toml").string();
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  // Where the wave key has the right hand (its target may be out of reach).
  auto fig = load_puppet("", (test::source_dir() / "config/rigs/figure.toml").string());
  ASSERT_TRUE(fig.ok()) << fig.error;
  Puppet& fp = **fig.value;
  auto keys = solve_keys(fp);
  ASSERT_TRUE(keys.ok()) << keys.error;
  const Vec2 wave_hand = eval_param(fp.feature_frame()->bindings()[size_t(fp.rig.find_handle("right-hand"))], (*keys.value)[0]);
  auto at_frame = [&](int frames, const char* handle) {
    o.frames = frames;
    auto s = LiveShow::load(show, o);
    EXPECT_TRUE(s.ok()) << s.error;
    if (!s.ok()) return Vec2(NAN, NAN);
    EXPECT_EQ((*s.value)->run(), 0);
    const Puppet& p = (*s.value)->puppet();
    return p.solver->handle_point(size_t(p.rig.find_handle(handle)));
  };
  const Vec2 up = at_frame(118, "right-hand");  // 1.97 s: knob 1 has been at the top since 1.7 s
  EXPECT_LT((up - wave_hand).norm(), 10.0) << up.transpose() << " vs " << wave_hand.transpose();  // knob 1 at the top: wave
  EXPECT_LT((at_frame(190, "right-hand") - Vec2(245, 250)).norm(), 15.0);  // and back to rest
  EXPECT_LT((at_frame(300, "right-foot") - Vec2(285, 330)).norm(), 20.0);  // blend.kick at 1
  EXPECT_LT(at_frame(300, "right-hand").y(), 200.0);                       // with blend.wave 0.6 on top
  const auto dir = test::temp_dir("keys-show");
  auto r = test::run_cli("run " + show + " --headless --stats " + (dir / "s.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream f(dir / "s.json");
  EXPECT_EQ(nlohmann::json::parse(f)["heap_allocations_after_warmup"], 0);
  std::ifstream in(show);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text.replace(text.find("morph.rest.wave"), 15, "morph.rest.wavy");
  text.replace(text.find("../rigs/figure.toml"), 19, (test::source_dir() / "config/rigs/figure.toml").string());
  std::ofstream(dir / "bad.toml") << text;
  auto bad = test::run_cli("run " + (dir / "bad.toml").string() + " --headless --frames 5");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("unknown key target 'morph.rest.wavy'"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("blend.wave, blend.kick"), std::string::npos) << bad.err;
}

// The singer's show (config/shows/singer.toml): pads swap the mouth (latched), M 1 blinks while
// held, M 2 toggles the blush; hidden members deform with the face; R 1 recalls the wave key over
// 0.5 s and R 2 rest over 0.8 s; nothing allocates after warm-up. Bad swap names: exit 2, file:line.
TEST(Live, SingerShowSwapsTriggersAndRecallsPosesSmoothly) {
  const std::string show = (test::source_dir() / "config/shows/singer.toml").string();
  auto sing = load_puppet("", (test::source_dir() / "config/rigs/singer.toml").string());
  ASSERT_TRUE(sing.ok()) << sing.error;
  Puppet& sp = **sing.value;
  auto keys = solve_keys(sp);
  ASSERT_TRUE(keys.ok()) << keys.error;
  const size_t hand = size_t(sp.rig.find_handle("right-hand"));
  const Vec2 wave_hand = eval_param(sp.feature_frame()->bindings()[hand], (*keys.value)[0]);
  auto shape = [&](const char* id) {
    for (size_t k = 0; k < sp.character.shapes.size(); ++k)
      if (sp.character.shapes[k].id == id) return k;
    ADD_FAILURE() << id;
    return size_t(0);
  };
  // Rest: the rig's defaults show.
  EXPECT_TRUE(sp.shown[shape("mouth-smile")] && sp.shown[shape("eyes-open")]);
  EXPECT_FALSE(sp.shown[shape("mouth-o")] || sp.shown[shape("eyes-shut")] || sp.shown[shape("cheeks")]);

  struct At {
    std::vector<char> shown;
    Vec2 hand;
    std::vector<Points> shapes;
  };
  auto at_frame = [&](int frames) {
    RunOptions o;
    o.headless = true;
    o.quiet = true;
    o.frames = frames;
    auto s = LiveShow::load(show, o);
    EXPECT_TRUE(s.ok()) << s.error;
    if (!s.ok()) return At{};
    EXPECT_EQ((*s.value)->run(), 0);
    const Puppet& p = (*s.value)->puppet();
    return At{p.shown, p.solver->handle_point(hand), p.shapes};
  };
  auto only = [&](const At& a, const char* id, std::initializer_list<const char*> hidden) {
    EXPECT_TRUE(a.shown[shape(id)]) << id;
    for (const char* h : hidden) EXPECT_FALSE(a.shown[shape(h)]) << h << " shows with " << id;
  };
  only(at_frame(61), "mouth-o", {"mouth-smile", "mouth-a", "mouth-e"});  // S 2 at 0.4 s, S 4 at 0.8 s
  only(at_frame(111), "eyes-shut", {"eyes-open"});                       // M 1 held from 1.8 s
  only(at_frame(126), "eyes-open", {"eyes-shut"});                       // released at 1.95 s
  EXPECT_TRUE(at_frame(151).shown[shape("cheeks")]);                      // M 2 at 2.2 s: on
  const At sway = at_frame(261);                                          // 4.33 s: sway and cheer blended
  EXPECT_TRUE(sway.shown[shape("cheeks")]);
  only(sway, "mouth-a", {"mouth-o", "mouth-smile"});                      // S 2 at 4.2 s
  EXPECT_FALSE(at_frame(291).shown[shape("cheeks")]);                     // M 2 again at 4.6 s: off
  // The hidden mouth moved with the face.
  auto centroid = [](const Points& p) {
    Vec2 c = Vec2::Zero();
    for (const Vec2& q : p) c += q;
    return Vec2(c / double(std::max<size_t>(1, p.size())));
  };
  const size_t face = shape("face"), mo = shape("mouth-o");
  const Vec2 face_moved = centroid(sway.shapes[face]) - centroid(sp.character.shapes[face].points);
  const Vec2 mouth_moved = centroid(sway.shapes[mo]) - centroid(sp.character.shapes[mo].points);
  EXPECT_GT(face_moved.norm(), 5.0);
  // Where the face's best rigid motion (its points' 2D Procrustes fit: the head turns as well
  // as moves) carries the mouth: the hidden mouth is there, to a small part of the face's travel.
  const Points& fr = sp.character.shapes[face].points;
  const Points& fp = sway.shapes[face];
  const Vec2 cr = centroid(fr), cp = centroid(fp);
  double sxx = 0, sxy = 0;
  for (size_t i = 0; i < fr.size(); ++i) {
    const Vec2 a = fr[i] - cr, b = fp[i] - cp;
    sxx += a.dot(b);
    sxy += a.x() * b.y() - a.y() * b.x();
  }
  const double ang = std::atan2(sxy, sxx);
  const Vec2 m0 = centroid(sp.character.shapes[mo].points) - cr;
  const Vec2 carried = cp + Vec2(std::cos(ang) * m0.x() - std::sin(ang) * m0.y(), std::sin(ang) * m0.x() + std::cos(ang) * m0.y());
  const Vec2 mouth_at = centroid(sway.shapes[mo]);
  std::cout << "the hidden mouth is " << (mouth_at - carried).norm() << " units from where the face carries it (the face moved " << face_moved.norm() << ")" << std::endl;
  EXPECT_LT((mouth_at - carried).norm(), 0.1 * face_moved.norm()) << mouth_at.transpose() << " vs carried by the face "
                                                                  << carried.transpose() << " (mouth moved " << mouth_moved.transpose()
                                                                  << ")";
  // R 1 at 5.6 s recalls wave over 0.5 s: on the way at 5.75 s, there by 6.2 s; R 2 at 7.4 s: rest by 8.3 s.
  const Vec2 rest_hand = sp.rig.handles[hand].rest;
  const double way = (wave_hand - rest_hand).norm();
  const double early = (at_frame(346).hand - rest_hand).norm();
  EXPECT_GT(early, 0.05 * way);
  EXPECT_LT(early, 0.6 * way);
  EXPECT_LT((at_frame(373).hand - wave_hand).norm(), 0.1 * way);
  EXPECT_LT((at_frame(499).hand - rest_hand).norm(), 0.1 * way);

  const auto dir = test::temp_dir("singer-show");
  auto r = test::run_cli("run " + show + " --headless --stats " + (dir / "s.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream f(dir / "s.json");
  EXPECT_EQ(nlohmann::json::parse(f)["heap_allocations_after_warmup"], 0);
  // A swap member that is no sub-shape: exit 2 naming the rig's line; an unknown swap target: the
  // show's line and the members there are.
  std::ifstream rin(test::source_dir() / "config/rigs/singer.toml");
  std::string rig((std::istreambuf_iterator<char>(rin)), std::istreambuf_iterator<char>());
  rig.replace(rig.find("../characters/singer.svg"), 24, (test::source_dir() / "config/characters/singer.svg").string());
  const std::string good_rig = rig;
  rig.replace(rig.find("\"mouth-o\"]"), 10, "\"mouth-u\"]");
  std::ofstream(dir / "bad_rig.toml") << rig;
  auto bad = test::run_cli("pose " + (test::source_dir() / "config/characters/singer.svg").string() + " --rig " +
                          (dir / "bad_rig.toml").string() + " -o " + (dir / "x.png").string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("bad_rig.toml:52: swap set 'mouth' names 'mouth-u', which is not a sub-shape"), std::string::npos)
      << bad.err;
  std::ofstream(dir / "rig.toml") << good_rig;
  std::ifstream in(show);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  text.replace(text.find("../rigs/singer.toml"), 19, (dir / "rig.toml").string());
  text.replace(text.find("swap.mouth.mouth-e"), 18, "swap.mouth.mouth-u");
  std::ofstream(dir / "bad.toml") << text;
  auto bad_show = test::run_cli("run " + (dir / "bad.toml").string() + " --headless --frames 5");
  EXPECT_EQ(bad_show.exit_code, 2);
  EXPECT_NE(bad_show.err.find("no swap set member 'mouth.mouth-u' (mouth.mouth-smile, mouth.mouth-a"), std::string::npos)
      << bad_show.err;
}

// SIGHUP reads the show file again: a bad edit is refused with file:line and the running show
// goes on; a good one is loaded; SIGTERM still ends the show cleanly.
TEST(Live, SighupReloadsAValidShowAndKeepsTheRunningOneOnABadEdit) {
  const auto dir = test::temp_dir("reload");
  const std::string show = (dir / "show.toml").string();
  const std::string rig = (test::source_dir() / "config/rigs/figure.toml").string();
  auto write = [&](const std::string& target) {
    std::ofstream(show) << "[show]\nrig = \"" << rig
                        << "\"\n[[device]]\nname = \"k\"\nsim = \"nanokontrol2\"\nscript = \"0 move knob1 1 over 0.5\"\n"
                           "[[binding]]\ndevice = \"k\"\ncontrol = \"cc 16\"\ntarget = \""
                        << target << "\"\n";
  };
  write("handle.head.x");
  const std::string out = (dir / "out.txt").string(), err = (dir / "err.txt").string();
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644), e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(o, 1);
    ::dup2(e, 2);
    ::execl(MARIONETTE_BINARY, MARIONETTE_BINARY, "run", show.c_str(), "--headless", "--frames", "100000000", nullptr);
    ::_exit(127);
  }
  auto slurp = [](const std::string& path) {
    std::ifstream in(path);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  auto wait_for = [&](const std::string& path, const std::string& what) {  // generous: a busy machine is slow
    for (int k = 0; k < 600; ++k) {
      if (slurp(path).find(what) != std::string::npos) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return false;
  };
  const bool started = wait_for(out, "running");
  if (started) {
    write("handle.nose.x");  // no such handle
    ::kill(pid, SIGHUP);
    EXPECT_TRUE(wait_for(err, "reload refused")) << slurp(err);
    EXPECT_NE(slurp(err).find(show + ":10: the rig has no handle 'nose'"), std::string::npos) << slurp(err);
    write("handle.head.y");
    ::kill(pid, SIGHUP);
    EXPECT_TRUE(wait_for(err, "reloaded " + show)) << slurp(err);
  }
  ::kill(pid, SIGTERM);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(started) << slurp(err);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status << " " << slurp(err);
}

// A kiosk runs fullscreen in a window (under Xvfb here) with the same frame code.
TEST(Live, KioskRunsFullscreenInAWindow) {
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) GTEST_SKIP() << "xvfb-run not installed";
  const auto dir = test::temp_dir("kiosk_run");
  const std::string show = (test::source_dir() / "config/shows/nanokontrol2.toml").string();
  const std::string cmd = "ASAN_OPTIONS=detect_leaks=0 " + test::xvfb_run() + " -s '-screen 0 800x600x24' '" + std::string(MARIONETTE_BINARY) +
                          "' run '" + show + "' --kiosk --frames 20 > '" + (dir / "out.txt").string() + "' 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::ifstream out(dir / "out.txt");
  const std::string text((std::istreambuf_iterator<char>(out)), {});
  EXPECT_NE(text.find("in a kiosk window"), std::string::npos) << text;
  EXPECT_NE(text.find("20 frames"), std::string::npos) << text;
  EXPECT_EQ(text.find("no window"), std::string::npos) << text;  // the window opened: no warning says otherwise
}

// The kiosk fills the screen, with or without a window manager (an X session started by
// xinit has none, and SDL's fullscreen window then kept the show's size: half the character on a
// 1280x1024 screen, none of it on 1920x1080). Judged on the screen's pixels, read from the X
// server: the stage (the show's 720x960 background, letterboxed) spans the screen's height and
// the width its aspect gives, centred, with black bars beside it.
TEST(Live, KioskFillsTheScreenWithAndWithoutAWindowManager) {
  if (std::system("command -v xvfb-run >/dev/null 2>&1") != 0) GTEST_SKIP() << "xvfb-run not installed";
  const std::string capture = std::string(MARIONETTE_BUILD_DIR) + "/tests/x_capture";
  const bool have_wm = std::system("command -v openbox >/dev/null 2>&1") == 0;
  if (!have_wm) std::cerr << "note: openbox is not installed; the kiosk is judged without a window manager only\n";
  const std::string show = (test::source_dir() / "config/shows/kiosk.toml").string();
  for (const auto& [w, h] : {std::pair{1280, 1024}, {1920, 1080}}) {
    for (const bool wm : {false, true}) {
      if (wm && !have_wm) continue;
      SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + (wm ? " with openbox" : " without a window manager"));
      const auto dir = test::temp_dir("kiosk_screen_" + std::to_string(w) + (wm ? "_wm" : ""));
      const std::string env = (dir / "env.txt").string(), png = (dir / "screen.png").string(), stop = (dir / "stop").string();
      std::filesystem::remove(env);
      std::filesystem::remove(stop);
      // The session: a window manager (or none), the show, and a wait for the test to say stop.
      const std::string inner = std::string(wm ? "openbox >/dev/null 2>&1 & sleep 1; " : "") + "echo \"$DISPLAY $XAUTHORITY\" > '" + env +
                                ".tmp'; mv '" + env + ".tmp' '" + env + "'; ASAN_OPTIONS=detect_leaks=0 '" + MARIONETTE_BINARY + "' run '" + show +
                                "' --kiosk --frames 100000 > '" + (dir / "show.log").string() + "' 2>&1 & p=$!; for i in $(seq 1200); do [ -e '" + stop +
                                "' ] && break; sleep 0.1; done; kill $p; wait $p";
      std::string quoted;
      for (char c : inner) quoted += c == '"' || c == '$' ? std::string("\\") + c : std::string(1, c);
      // (A display number of its own: two xvfb-run -a started at once by parallel tests race for 99.)
      const std::string cmd = "timeout 150 xvfb-run -n " + std::to_string(200 + ::getpid() % 500) + " -a -s '-screen 0 " +
                              std::to_string(w) + "x" + std::to_string(h) +
                              "x24' sh -c \"" + quoted + "\" >/dev/null 2>&1 &";
      ASSERT_EQ(std::system(cmd.c_str()), 0);
      std::string display, xauth;
      for (int k = 0; k < 600 && display.empty(); ++k) {
        std::ifstream e(env);
        e >> display >> xauth;
        if (display.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
      }
      ASSERT_FALSE(display.empty()) << "no X session";
      // Until the stage shows (generous: a busy machine is slow to start a show).
      std::optional<Image> screen;
      auto px = [&](int x, int y) { return &screen->rgba[(size_t(y) * size_t(screen->width) + size_t(x)) * 4]; };
      auto black = [&](int x, int y) { const uint8_t* p = px(x, y); return p[0] < 8 && p[1] < 8 && p[2] < 8; };
      for (int k = 0; k < 600; ++k) {
        const std::string q = "DISPLAY=" + display + " XAUTHORITY=" + xauth + " '" + capture + "' '" + png + "' 2>/dev/null";
        if (std::system(q.c_str()) == 0) {
          auto img = read_png_image(png);
          if (img.ok() && img.value->width == w && img.value->height == h) {
            screen = std::move(*img.value);
            if (!black(w / 2, 2) && !black(w / 2, h - 3)) break;  // the stage, top to bottom
          }
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
      }
      std::ofstream(stop) << "stop";
      std::ifstream log(dir / "show.log");
      SCOPED_TRACE("the show said: " + std::string(std::istreambuf_iterator<char>(log), {}) + " on " + display);
      ASSERT_TRUE(screen.has_value()) << "no capture of the screen";
      EXPECT_FALSE(black(w / 2, 2)) << "the stage reaches the top of the screen";
      EXPECT_FALSE(black(w / 2, h - 3)) << "and its bottom";
      EXPECT_FALSE(black(w / 2, h / 2)) << "it is in the middle";
      // Its width along the middle row: 720/960 of the screen's height, centred.
      int left = 0, right = w - 1;
      while (left < w && black(left, h / 2)) ++left;
      while (right > 0 && black(right, h / 2)) --right;
      const double expect = double(h) * 720.0 / 960.0;
      EXPECT_NEAR(right - left + 1, expect, 0.02 * expect);
      EXPECT_NEAR((left + right) / 2.0, w / 2.0, 0.02 * w);
      EXPECT_TRUE(black(2, h / 2) && black(w - 3, h / 2)) << "black bars beside the stage";
    }
  }
}

// A display that does not answer: SDL falls back to its offscreen driver, whose "window" shows
// nothing. A kiosk ran a whole show so on CI (the screen stayed black, and the show said "in a
// kiosk window"). A show asked for a window says there is none and runs headless; a kiosk,
// which would show no one anything and fill its disk with frames, says why and stops, so its
// service manager starts it again. So does a kiosk with no display at all.
TEST(Live, NoScreenIsSaidAndAKioskWithoutOneStops) {
  int n = 900 + ::getpid() % 90;  // a display number no X server is on
  while (std::filesystem::exists("/tmp/.X11-unix/X" + std::to_string(n))) ++n;
  // (as every test here that starts SDL's video: libdbus, which SDL loads, leaks a buffer)
  const std::string nowhere = "env -u WAYLAND_DISPLAY -u SDL_VIDEODRIVER ASAN_OPTIONS=detect_leaks=0 XDG_RUNTIME_DIR= DISPLAY=:" + std::to_string(n);
  const std::string kiosk = (test::source_dir() / "config/shows/kiosk.toml").string();
  auto r = test::run_cli("run '" + kiosk + "' --kiosk --frames 30", nowhere);
  EXPECT_NE(r.exit_code, 0) << r.out;
  EXPECT_NE(r.err.find(kiosk + ": a kiosk needs a screen"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("SDL could not reach DISPLAY=:" + std::to_string(n)), std::string::npos) << r.err;
  EXPECT_EQ(r.out.find("in a kiosk window"), std::string::npos) << r.out;
  r = test::run_cli("run '" + kiosk + "' --kiosk --frames 30", "env -u DISPLAY -u WAYLAND_DISPLAY -u SDL_VIDEODRIVER XDG_RUNTIME_DIR=");
  EXPECT_NE(r.exit_code, 0) << r.out;
  EXPECT_NE(r.err.find("a kiosk needs a screen, and there is none (DISPLAY, WAYLAND_DISPLAY and SDL_VIDEODRIVER are unset)"), std::string::npos)
      << r.err;
  // Headless, a kiosk plays as before.
  r = test::run_cli("run '" + kiosk + "' --kiosk --headless --frames 5", nowhere);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("5 frames"), std::string::npos) << r.out;
  // A show asked for a window runs headless and says why (its frames go to marionette-frames/ in
  // the folder it runs in).
  const auto dir = test::temp_dir("no_screen");
  const std::string show = (test::source_dir() / "config/shows/nanokontrol2.toml").string();
  r = test::run_cli("run '" + show + "' --frames 20", "cd '" + dir.string() + "' && " + nowhere);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("no window (no display: SDL could not reach DISPLAY=:" + std::to_string(n)), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("running headless"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("in a window"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir / "marionette-frames")) << r.out;
}

// The shipped kiosk unit names SDL_VIDEODRIVER=kmsdrm with neither X nor Wayland: the show asks
// that driver for its screen (it ran headless before, as if there were no display at all).
TEST(Live, AKioskOnANamedVideoDriverAsksThatDriver) {
  if (std::filesystem::exists("/dev/dri")) GTEST_SKIP() << "this machine has /dev/dri: a kiosk there would take the console";
  const std::string kiosk = (test::source_dir() / "config/shows/kiosk.toml").string();
  auto r = test::run_cli("run '" + kiosk + "' --kiosk --frames 30", "env -u DISPLAY -u WAYLAND_DISPLAY ASAN_OPTIONS=detect_leaks=0 XDG_RUNTIME_DIR= SDL_VIDEODRIVER=kmsdrm");
  EXPECT_NE(r.exit_code, 0) << r.out;
  EXPECT_NE(r.err.find(kiosk + ": a kiosk needs a screen, and there is none (no display: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("kmsdrm"), std::string::npos) << r.err;
}

// Every show shipped in config/shows/ reads and checks (show, rig, character, bindings, attract).
TEST(Live, EveryShippedShowValidates) {
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(test::source_dir() / "config/shows")) {
    if (e.path().extension() != ".toml") continue;
    EXPECT_EQ(LiveShow::validate(e.path().string()), "") << e.path();
    ++n;
  }
  EXPECT_GE(n, 11);
}

}  // namespace
}  // namespace mar
