// Show files are parsed once, from default_show(), and resolved against the rig the
// [show] table names (handles, and the settings the loop and the solver offer).
#include "app/show.h"
#include "test_util.h"

#include <SDL2/SDL.h>
#include <gtest/gtest.h>

namespace mar {
namespace {

ShowRig two_handles() {
  ShowRig r;
  r.handles = {"head", "hand"};
  r.rest = {Vec2(0, 0), Vec2(10, 0)};
  r.diag = 100;
  r.settings = {{"iterations", std::pair<double, double>(3, 9)}, {"rigidity", std::nullopt}};
  return r;
}

TEST(Show, DefaultsComeFromDefaultShow) {
  const ShowConfig d = default_show();
  const std::string path = test::write_temp("minimal.toml", "[show]\nrig = \"r.toml\"\n");
  int calls = 0;
  auto s = load_show(path, [&](const ShowConfig& header) {
    ++calls;
    EXPECT_EQ(header.rig, (std::filesystem::path(path).parent_path() / "r.toml").string());
    return Result<ShowRig>::success(two_handles());
  });
  ASSERT_TRUE(s.ok()) << s.error;
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(s.value->rate_hz, d.rate_hz);
  EXPECT_EQ(s.value->iterations, d.iterations);
  EXPECT_EQ(s.value->min_iterations, d.min_iterations);
  EXPECT_EQ(s.value->width, d.width);
  EXPECT_EQ(s.value->background, d.background);
  EXPECT_EQ(d.rate_hz, 60);
  EXPECT_EQ(d.iterations, 8);
  EXPECT_TRUE(d.hud);
}

// A pointer binding's area: four numbers (character units) or "canvas"; anything else is said
// with its line (a "canvas" area once crashed the reader, which went on to read four numbers).
TEST(Show, APointersAreaIsFourNumbersOrTheCanvas) {
  auto load = [](const std::string& name, const std::string& area) {
    const std::string path = test::write_temp(name, "[show]\nrig = \"r.toml\"\n[[device]]\nname = \"pen\"\nsim = \"pen_tablet\"\n"
                                                    "[[binding]]\ndevice = \"pen\"\ncontrol = \"pointer\"\ntarget = \"grab\"\narea = " + area + "\n");
    return load_show(path, [](const ShowConfig&) { return Result<ShowRig>::success(two_handles()); });
  };
  auto canvas = load("area_canvas.toml", "\"canvas\"");
  ASSERT_TRUE(canvas.ok()) << canvas.error;
  EXPECT_TRUE(canvas.value->bindings.back().tf.area_canvas);
  auto box = load("area_box.toml", "[0, 0, 20, 10]");
  ASSERT_TRUE(box.ok()) << box.error;
  EXPECT_FALSE(box.value->bindings.back().tf.area_canvas);
  EXPECT_EQ(box.value->bindings.back().tf.area[2], 20);
  auto bad = load("area_bad.toml", "\"everywhere\"");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error.find(":10: area must be [x0, y0, x1, y1] (character units) or \"canvas\""), std::string::npos) << bad.error;
}

// [[group]] follow names the handle whose moves the group takes; it is said with its line when
// it names no handle, one of the group's own, or comes with pivot_handle.
TEST(Show, AGroupFollowsAHandleTheRigHas) {
  auto load = [](const std::string& name, const std::string& group) {
    return load_show(test::write_temp(name, "[show]\nrig = \"r.toml\"\n[[group]]\nname = \"arm\"\nhandles = [\"hand\"]\n" + group),
                     [](const ShowConfig&) { return Result<ShowRig>::success(two_handles()); });
  };
  auto ok = load("follow_ok.toml", "pivot = [5, 0]\nfollow = \"head\"\n");
  ASSERT_TRUE(ok.ok()) << ok.error;
  ASSERT_EQ(ok.value->groups.size(), 1u);
  EXPECT_EQ(ok.value->groups[0].follow, 0);
  auto none = load("follow_none.toml", "pivot = [5, 0]\n");
  ASSERT_TRUE(none.ok()) << none.error;
  EXPECT_EQ(none.value->groups[0].follow, -1);
  auto missing = load("follow_missing.toml", "pivot = [5, 0]\nfollow = \"tail\"\n");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error.find(":7: the rig has no handle 'tail'"), std::string::npos) << missing.error;
  auto own = load("follow_own.toml", "pivot = [5, 0]\nfollow = \"hand\"\n");
  ASSERT_FALSE(own.ok());
  EXPECT_NE(own.error.find(":7: [[group]] arm follows one of its own handles"), std::string::npos) << own.error;
  auto both = load("follow_both.toml", "pivot_handle = \"head\"\nfollow = \"head\"\n");
  ASSERT_FALSE(both.ok());
  EXPECT_NE(both.error.find(":7: [[group]] arm: follow moves a pivot"), std::string::npos) << both.error;
}

TEST(Show, SolverTargetsNameTheSettingsTheRigOffers) {
  const std::string path = test::write_temp("settings.toml", R"([show]
rig = "r.toml"
iterations = 9
min_iterations = 3
[[device]]
name = "k"
sim = "nanokontrol2"
[[binding]]
device = "k"
control = "cc 16"
target = "solver.iterations"
[[binding]]
device = "k"
control = "cc 17"
target = "solver.rigidity"
range = [0.5, 4.0]
)");
  auto s = load_show(path, [](const ShowConfig&) { return Result<ShowRig>::success(two_handles()); });
  ASSERT_TRUE(s.ok()) << s.error;
  ASSERT_EQ(s.value->bindings.size(), 2u);
  EXPECT_EQ(s.value->bindings[0].target, TargetKind::Setting);
  EXPECT_EQ(s.value->bindings[0].index, 0);
  EXPECT_EQ(s.value->bindings[0].tf.lo, 3);  // the setting's default range
  EXPECT_EQ(s.value->bindings[0].tf.hi, 9);
  EXPECT_EQ(s.value->bindings[1].index, 1);
  EXPECT_EQ(s.value->bindings[1].tf.hi, 4.0);
}

TEST(Show, AnUnknownSettingListsTheOnesOfferedWithFileAndLine) {
  const std::string path = test::write_temp("bad-setting.toml", R"([show]
rig = "r.toml"
[[device]]
name = "k"
sim = "nanokontrol2"
[[binding]]
device = "k"
control = "cc 16"
target = "solver.half_width"
)");
  auto s = load_show(path, [](const ShowConfig&) { return Result<ShowRig>::success(two_handles()); });
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error.find(path + ":9:"), std::string::npos) << s.error;
  EXPECT_NE(s.error.find("solver.iterations, solver.rigidity"), std::string::npos) << s.error;
}

// Secondary motion: physics.NAME.strength|mix and physics.wind|gravity|reset name settings
// with their default ranges; [physics] sets the world; a wrong name lists the right ones.
TEST(Show, PhysicsTargetsAndThePhysicsTable) {
  auto rig = [] {
    ShowRig r = two_handles();
    for (const char* n : {"physics.hair.strength", "physics.hair.mix", "physics.wind", "physics.gravity", "physics.reset"})
      r.settings.push_back({n, std::pair<double, double>(0, std::string(n) == "physics.wind" ? 2000 : 1)});
    return Result<ShowRig>::success(r);
  };
  const std::string head = R"([show]
rig = "r.toml"
[physics]
rate = 60
gravity = [0, 500]
wind = [30, 0]
[[device]]
name = "k"
sim = "nanokontrol2"
[[binding]]
device = "k"
control = "cc 16"
)";
  auto s = load_show(test::write_temp("physics.toml", head + "target = \"physics.hair.mix\"\n"), [&](const ShowConfig&) { return rig(); });
  ASSERT_TRUE(s.ok()) << s.error;
  EXPECT_EQ(s.value->physics.rate, 60);
  EXPECT_EQ(s.value->physics.gravity, Vec2(0, 500));
  EXPECT_EQ(s.value->physics.wind, Vec2(30, 0));
  EXPECT_EQ(s.value->bindings[0].target, TargetKind::Setting);
  EXPECT_EQ(s.value->bindings[0].index, 3);
  auto w = load_show(test::write_temp("physics-wind.toml", head + "target = \"physics.wind\"\n"), [&](const ShowConfig&) { return rig(); });
  ASSERT_TRUE(w.ok()) << w.error;
  EXPECT_EQ(w.value->bindings[0].tf.hi, 2000) << "the setting's default range";
  const std::string bad_path = test::write_temp("physics-bad.toml", head + "target = \"physics.hare.mix\"\n");
  auto bad = load_show(bad_path, [&](const ShowConfig&) { return rig(); });
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error.find(bad_path + ":13: unknown physics setting 'physics.hare.mix' (physics.hair.strength, physics.hair.mix"),
            std::string::npos)
      << bad.error;
  auto none = load_show(test::write_temp("physics-none.toml", head + "target = \"physics.wind\"\n"),
                        [](const ShowConfig&) { return Result<ShowRig>::success(two_handles()); });
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error.find("the rig has no [[physics]] chains"), std::string::npos) << none.error;
  auto rate = load_show(test::write_temp("physics-rate.toml", "[show]\nrig = \"r.toml\"\n[physics]\nrate = 500\n"),
                        [&](const ShowConfig&) { return rig(); });
  ASSERT_FALSE(rate.ok());
  EXPECT_NE(rate.error.find(":4: rate must be 30..240"), std::string::npos) << rate.error;
}

TEST(Show, TheRigLoadersErrorIsReturnedAndASyntaxErrorNeverLoadsTheRig) {
  const std::string good = test::write_temp("rig-error.toml", "[show]\nrig = \"r.toml\"\n");
  auto s = load_show(good, [](const ShowConfig&) { return Result<ShowRig>::failure("r.toml:3: broken rig"); });
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error, "r.toml:3: broken rig");
  const std::string bad = test::write_temp("syntax.toml", "[show]\nrig = \"r.toml\"\n[[device]\n");
  bool called = false;
  auto t = load_show(bad, [&](const ShowConfig&) {
    called = true;
    return Result<ShowRig>::success(two_handles());
  });
  ASSERT_FALSE(t.ok());
  EXPECT_FALSE(called);
  EXPECT_NE(t.error.find(bad + ":3:"), std::string::npos) << t.error;
}

}  // namespace
}  // namespace mar

namespace mar {
namespace {

ShowRig singer_rig() {
  ShowRig r = two_handles();
  r.swaps = {{"mouth", {"m-a", "m-o"}}};
  r.triggers = {"blink"};
  r.keys = {"wave"};
  return r;
}

// swap.SET.MEMBER, trigger.NAME and pose.KEY (a rig key, along the interpolation) resolve against
// the rig; swaps latch unless told momentary; transition, ease, threshold and return are read
// where they make sense and refused (file:line) where they do not.
TEST(Show, SwapTriggerAndRecallTargetsWithTheirKeys) {
  const std::string head = R"([show]
rig = "r.toml"
[[device]]
name = "k"
sim = "nanokontrol2"
[[device]]
name = "pen"
sim = "pen_tablet"
)";
  const std::string path = test::write_temp("swaps.toml", head + R"([[binding]]
device = "k"
control = "cc 32"
target = "swap.mouth.m-o"
threshold = 0.2
[[binding]]
device = "k"
control = "cc 33"
target = "trigger.blink"
[[binding]]
device = "k"
control = "cc 34"
target = "pose.wave"
transition = 0.4
ease = "out"
[[binding]]
device = "k"
control = "cc 35"
target = "pose.rest"
[[binding]]
device = "pen"
control = "pointer"
target = "handle.hand"
return = 0.3
)");
  auto s = load_show(path, [](const ShowConfig&) { return Result<ShowRig>::success(singer_rig()); });
  ASSERT_TRUE(s.ok()) << s.error;
  const auto& b = s.value->bindings;
  ASSERT_EQ(b.size(), 5u);
  EXPECT_EQ(b[0].target, TargetKind::Swap);
  EXPECT_EQ(b[0].index, 0);
  EXPECT_EQ(b[0].member, 1);
  EXPECT_TRUE(b[0].tf.toggle);  // latched
  EXPECT_EQ(b[0].tf.threshold, 0.2);
  EXPECT_EQ(b[1].target, TargetKind::Trigger);
  EXPECT_FALSE(b[1].tf.toggle);  // momentary
  EXPECT_EQ(b[2].target, TargetKind::Recall);
  EXPECT_EQ(b[2].index, 0);
  EXPECT_EQ(b[2].tf.transition, 0.4);
  EXPECT_EQ(b[2].tf.ease, Ease::Out);
  EXPECT_EQ(b[3].target, TargetKind::Recall);
  EXPECT_EQ(b[3].index, -1);
  EXPECT_EQ(b[4].tf.ret, 0.3);

  struct Case {
    const char* binding;
    const char* expect;
  };
  const Case cases[] = {
      {"device = \"k\"\ncontrol = \"cc 32\"\ntarget = \"swap.mouth.m-u\"\n", ":12: no swap set member 'mouth.m-u' (mouth.m-a, mouth.m-o)"},
      {"device = \"k\"\ncontrol = \"cc 32\"\ntarget = \"trigger.wink\"\n", ":12: no trigger 'wink' (blink)"},
      {"device = \"k\"\ncontrol = \"cc 32\"\ntarget = \"pose.dance\"\n", ":12: no [[pose]] or rig key named 'dance' (wave)"},
      {"device = \"k\"\ncontrol = \"cc 32\"\ntarget = \"handle.hand.x\"\ntransition = 1\n", ":13: transition goes with a pose.NAME target"},
      {"device = \"k\"\ncontrol = \"cc 32\"\ntarget = \"handle.hand\"\nreturn = 0.2\n", ":13: return goes with a pointer"},
      {"device = \"pen\"\ncontrol = \"pointer\"\ntarget = \"handle.hand\"\nreturn = \"soon\"\n", ":13: return must be"},
      {"device = \"k\"\ncontrol = \"cc 32\"\ntarget = \"trigger.blink\"\nthreshold = 0\n", ":13: threshold must be in (0, 1]"},
      {"device = \"k\"\ncontrol = \"cc 32\"\ntarget = \"pose.wave\"\nease = \"bounce\"\n", ":13: ease must be linear, in, out or in_out"},
  };
  for (const Case& c : cases) {
    const std::string bad = test::write_temp("bad-swap.toml", head + "[[binding]]\n" + c.binding);
    auto e = load_show(bad, [](const ShowConfig&) { return Result<ShowRig>::success(singer_rig()); });
    ASSERT_FALSE(e.ok()) << c.binding;
    EXPECT_NE(e.error.find(bad + c.expect), std::string::npos) << e.error;
  }
}

}  // namespace
}  // namespace mar

namespace mar {
namespace {

// Numbers that become integers or nanoseconds are range-checked before any cast: 1e300 iterations,
// a negative seed or a year of debounce are errors with file:line, never undefined behaviour.
TEST(Show, HugeOrNegativeNumbersAreRefusedBeforeTheyAreCast) {
  struct Case {
    const char* text;
    const char* expect;
  };
  const Case cases[] = {
      {"[show]\nrig = \"r.toml\"\niterations = 1e300\n", ":3: iterations must be an integer 1..200"},
      {"[show]\nrig = \"r.toml\"\nmin_iterations = -5\n", ":3: min_iterations must be an integer 1..200"},
      {"[show]\nrig = \"r.toml\"\n[display]\nwidth = 1e20\n", ":4: width must be an integer 16..8192"},
      // fuzz_show_toml: past int64's range, toml++'s own conversion is undefined (now never made)
      {"[show]\nrig = \"r.toml\"\n[display]\nheight = 4e048\n", ":4: height must be an integer 16..8192"},
      {"[show]\nrig = \"r.toml\"\n[display]\nheight = 640.5\n", ":4: height must be an integer 16..8192"},
      {"[show]\nrig = \"r.toml\"\n[[device]]\nname = \"k\"\nsim = \"knob_box\"\nseed = -1\n", ":6: seed must be an integer 0..2147483647"},
      {"[show]\nrig = \"r.toml\"\n[[device]]\nname = \"k\"\nsim = \"knob_box\"\nbounce_ms = 1e300\n", ":6: bounce_ms must be 0..10000 ms"},
      {"[show]\nrig = \"r.toml\"\n[[device]]\nname = \"k\"\nsim = \"knob_box\"\ndebounce_ms = 3.2e10\n", ":6: debounce_ms must be 0..10000 ms"},
  };
  for (const Case& c : cases) {
    const std::string path = test::write_temp("huge.toml", c.text);
    auto s = load_show(path, [](const ShowConfig&) { return Result<ShowRig>::success(two_handles()); });
    ASSERT_FALSE(s.ok()) << c.text;
    EXPECT_NE(s.error.find(path + c.expect), std::string::npos) << s.error;
  }
}

}  // namespace
}  // namespace mar

namespace mar {
namespace {

// [kiosk]: fullscreen on a display, and only the exit chord quits (Escape, q and h do nothing);
// a bad chord is refused with file:line.
TEST(Show, KioskTableAndItsExitChord) {
  const std::string path = test::write_temp("kiosk.toml", "[show]\nrig = \"r.toml\"\n[kiosk]\ndisplay = 1\nexit_chord = \"ctrl+alt+q\"\n");
  auto s = load_show(path, [](const ShowConfig&) { return Result<ShowRig>::success(two_handles()); });
  ASSERT_TRUE(s.ok()) << s.error;
  const ShowConfig::Kiosk& k = s.value->kiosk;
  EXPECT_TRUE(k.enabled);
  EXPECT_EQ(k.display, 1);
  EXPECT_EQ(window_key(k, SDLK_ESCAPE, 0), WindowKey::None);
  EXPECT_EQ(window_key(k, SDLK_q, 0), WindowKey::None);
  EXPECT_EQ(window_key(k, SDLK_h, 0), WindowKey::None);
  EXPECT_EQ(window_key(k, SDLK_q, KMOD_LCTRL), WindowKey::None);
  EXPECT_EQ(window_key(k, SDLK_q, KMOD_LCTRL | KMOD_RALT), WindowKey::Quit);
  EXPECT_EQ(window_key(k, SDLK_q, KMOD_RCTRL | KMOD_LALT | KMOD_SHIFT), WindowKey::Quit);
  ShowConfig::Kiosk none;  // not a kiosk: Escape and q quit, h toggles the HUD
  EXPECT_EQ(window_key(none, SDLK_ESCAPE, 0), WindowKey::Quit);
  EXPECT_EQ(window_key(none, SDLK_h, 0), WindowKey::ToggleHud);
  ShowConfig::Kiosk no_chord;  // a kiosk without a chord: only a signal ends it
  no_chord.enabled = true;
  EXPECT_EQ(window_key(no_chord, SDLK_ESCAPE, KMOD_CTRL), WindowKey::None);
  struct Case {
    const char* chord;
    const char* expect;
  };
  const Case cases[] = {{"ctrl+alt+nosuchkey", ":4: exit_chord: unknown key 'nosuchkey'"},
                        {"q", ":4: exit_chord needs a modifier"},
                        {"meta+q", ":4: exit_chord: unknown modifier 'meta'"}};
  for (const Case& c : cases) {
    const std::string bad = test::write_temp("kiosk-bad.toml", std::string("[show]\nrig = \"r.toml\"\n[kiosk]\nexit_chord = \"") + c.chord + "\"\n");
    auto e = load_show(bad, [](const ShowConfig&) { return Result<ShowRig>::success(two_handles()); });
    ASSERT_FALSE(e.ok()) << c.chord;
    EXPECT_NE(e.error.find(bad + c.expect), std::string::npos) << e.error;
  }
}

TEST(Show, OutputAndOscOutTables) {
  auto ok = load_show(test::write_temp("outs.toml", "[show]\nrig = \"r.toml\"\n[output]\npipewire = true\n[osc_out]\nport = 9001\nhost = \"10.0.0.5\"\nrate = 20\nprefix = \"/puppet\"\n"),
                      [](const ShowConfig&) { return Result<ShowRig>::success(two_handles()); });
  ASSERT_TRUE(ok.ok()) << ok.error;
  EXPECT_TRUE(ok.value->out_pipewire);
  EXPECT_EQ(ok.value->osc_out.port, 9001);
  EXPECT_EQ(ok.value->osc_out.host, "10.0.0.5");
  EXPECT_EQ(ok.value->osc_out.rate, 20.0);
  EXPECT_EQ(ok.value->osc_out.prefix, "/puppet");
  auto plain = load_show(test::write_temp("outs-none.toml", "[show]\nrig = \"r.toml\"\n"),
                         [](const ShowConfig&) { return Result<ShowRig>::success(two_handles()); });
  ASSERT_TRUE(plain.ok());
  EXPECT_EQ(plain.value->osc_out.port, 0) << "off unless asked";
  EXPECT_EQ(plain.value->osc_out.host, "127.0.0.1") << "loopback unless told otherwise";
  struct Case {
    const char* table;
    const char* expect;
  };
  const Case cases[] = {{"[osc_out]\nhost = \"x\"\n", ":3: [osc_out] needs a port"},
                        {"[osc_out]\nport = 70000\n", ":4: port"},
                        {"[osc_out]\nport = 9000\nrate = 0\n", ":5: [osc_out] rate must be 1..1000"},
                        {"[osc_out]\nport = 9000\nprefix = \"nope\"\n", ":5: [osc_out] prefix must be an OSC address"},
                        {"[osc_out]\nport = 9000\nbogus = 1\n", "bogus"},
                        {"[output]\npipewire = \"yes\"\n", ":4: pipewire"}};
  for (const Case& c : cases) {
    const std::string bad = test::write_temp("outs-bad.toml", std::string("[show]\nrig = \"r.toml\"\n") + c.table);
    auto e = load_show(bad, [](const ShowConfig&) { return Result<ShowRig>::success(two_handles()); });
    ASSERT_FALSE(e.ok()) << c.table;
    EXPECT_NE(e.error.find(c.expect), std::string::npos) << c.table << ": " << e.error;
  }
}

}  // namespace
}  // namespace mar
