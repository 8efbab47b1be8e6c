// Controllers that light up from the show's state (app/loop/leds.h): simulated APC mini mk2,
// X-Touch Mini, MIDImix and nanoKONTROL2 units, each named by its profile, are pressed and turned by their
// scripts; what their simulators show is what the show is doing: a toggled trigger lit while on,
// the swapped-in member lit in its colour and the others dark, the current pose's button lit,
// an encoder's ring following the handle it moves. Echoes of the lights are dropped.
#include "app/live.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <map>
#include <sstream>

namespace mar {
namespace {

std::map<std::string, int> lights(const nlohmann::json& stats, const std::string& device) {
  std::map<std::string, int> out;
  const auto& shown = stats["leds"]["simulators_show"];
  if (!shown.contains(device)) return out;
  std::istringstream in(shown[device].get<std::string>());
  for (std::string w; in >> w;) out[w.substr(0, w.find('='))] = std::stoi(w.substr(w.find('=') + 1));
  return out;
}

TEST(LiveLeds, LightsShowTheShowsStateNotThePresses) {
  const std::string rig = (test::source_dir() / "config/rigs/singer.toml").string();
  const std::string path = test::write_temp("leds.toml", "[show]\nrig = \"" + rig + R"("
rate = 60
[display]
width = 160
height = 200
[[device]]
name = "apc"
type = "sim"
profile = "apc_mini_mk2"
script = """
0.2 press pad_r1c1
0.5 press pad_r1c2
0.8 press pad_r1c3
1.1 press pad_r1c1
"""
[[device]]
name = "xtouch"
type = "sim"
profile = "xtouch_mini"
script = """
0 move encoder1 0
0.3 press button1
0.4 move encoder1 1 over 1
1.6 press button2
"""
[[device]]
name = "mix"
type = "sim"
profile = "midimix"
script = "0.3 press mute1"
[[device]]
name = "korg"
type = "sim"
profile = "nanokontrol2"
[[pose]]
name = "up"
handles = { left-hand = [60.0, 40.0] }
[[pose]]
name = "down"
handles = { left-hand = [60.0, 160.0] }
[[binding]]
device = "apc"
control = "pad_r1c1"
target = "trigger.blush"
button = "toggle"
led = "red"
[[binding]]
device = "apc"
control = "pad_r1c2"
target = "swap.mouth.mouth-o"
led = "blue"
[[binding]]
device = "apc"
control = "pad_r1c3"
target = "swap.mouth.mouth-a"
[[binding]]
device = "xtouch"
control = "encoder1"
target = "handle.head.x"
[[binding]]
device = "xtouch"
control = "button1"
target = "pose.up"
[[binding]]
device = "xtouch"
control = "button2"
target = "pose.down"
[[binding]]
device = "korg"
control = "solo1"
target = "pose.up"
[[binding]]
device = "mix"
control = "mute1"
target = "trigger.blink"
button = "toggle"
)");
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  auto s = LiveShow::load(path, o);
  ASSERT_TRUE(s.ok()) << s.error;
  LiveShow& show = **s.value;
  auto run_to = [&](double t) {
    while (double(show.frames()) / 60 <= t) show.frame(int64_t(double(show.frames()) * 1e9 / 60));
    return nlohmann::json::parse(show.stats_json());
  };
  auto j = run_to(0.1);
  EXPECT_EQ(lights(j, "apc")["pad_r1c1"], 0);  // every light set at the start: dark
  EXPECT_EQ(lights(j, "apc")["pad_r1c2"], 0);
  EXPECT_EQ(lights(j, "xtouch")["ring1"], 7);  // the handle at the middle of the binding's range
  j = run_to(0.35);
  EXPECT_EQ(lights(j, "apc")["pad_r1c1"], 5);   // blush on: red
  EXPECT_EQ(lights(j, "xtouch")["button1"], 1); // pose "up" is current
  EXPECT_EQ(lights(j, "mix")["mute1"], 127);    // blink toggled on
  EXPECT_EQ(lights(j, "korg")["solo1"], 127);   // pose "up": the nanoKONTROL2, set to External LEDs first
  EXPECT_EQ(j["leds"]["korg_led_mode"], "switched");
  j = run_to(0.6);
  EXPECT_EQ(lights(j, "apc")["pad_r1c2"], 45);  // mouth-o shows: blue
  EXPECT_EQ(lights(j, "apc")["pad_r1c3"], 0);
  j = run_to(0.9);
  EXPECT_EQ(lights(j, "apc")["pad_r1c2"], 0);   // swapped out: dark
  EXPECT_EQ(lights(j, "apc")["pad_r1c3"], 21);  // mouth-a: the profile's green
  EXPECT_EQ(lights(j, "apc")["pad_r1c1"], 5);   // (the press let go: still on, it toggled)
  const int ring_mid = lights(j, "xtouch")["ring1"];
  EXPECT_GT(ring_mid, 3);
  EXPECT_LT(ring_mid, 11);
  j = run_to(1.5);
  EXPECT_EQ(lights(j, "apc")["pad_r1c1"], 0);   // toggled off
  EXPECT_EQ(lights(j, "xtouch")["ring1"], 13);  // the encoder at its end
  EXPECT_EQ(lights(j, "xtouch")["button1"], 1);
  j = run_to(1.8);
  EXPECT_EQ(lights(j, "xtouch")["button1"], 0);  // another pose is current
  EXPECT_EQ(lights(j, "xtouch")["button2"], 1);
  EXPECT_EQ(lights(j, "korg")["solo1"], 0);
  EXPECT_GT(j["leds"]["sent"].get<int>(), 10);
  EXPECT_EQ(j["leds"]["failed"], 0);
  EXPECT_EQ(j["leds"]["init_messages"], 9);  // the X-Touch Mini: standard mode, eight fan rings
  EXPECT_EQ(j["heap_allocations_after_warmup"], 0);
}

TEST(LiveLeds, ABindingsColourMustBeOneOfItsPalette) {
  const std::string rig = (test::source_dir() / "config/rigs/singer.toml").string();
  const std::string path = test::write_temp("leds_bad.toml", "[show]\nrig = \"" + rig + R"("
[[device]]
name = "apc"
type = "sim"
profile = "apc_mini_mk2"
[[binding]]
device = "apc"
control = "pad_r1c1"
target = "trigger.blush"
led = "mauve"
)");
  const std::string err = LiveShow::validate(path);
  EXPECT_NE(err.find("leds_bad.toml:11: no colour 'mauve' (off, white, red"), std::string::npos) << err;
}

}  // namespace
}  // namespace mar
