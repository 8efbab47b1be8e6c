// Motion on the music: a simulated nanoKONTROL2 sends MIDI clock at 120 BPM with 1 ms of
// jitter, and a breath with sync = "beat" follows its beats; [physics] sync = "beat" pulses the
// wind on them; a bad sync value is refused with the line.
#include "app/live.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>

namespace mar {
namespace {

std::string music_show(const std::string& extra) {
  const std::string rig = (test::source_dir() / "config/rigs/figure.toml").string();
  return test::write_temp("music.toml", "[show]\nrig = \"" + rig + "\"\nrate = 120\n[display]\nwidth = 160\nheight = 200\n" +
                                            "[[device]]\nname = \"korg\"\nsim = \"nanokontrol2\"\n"
                                            "script = \"0.5 clock 120 jitter 0.001 for 6\"\n" + extra);
}

TEST(LiveMusic, ABreathOnTheBeatFollowsTheClocksBeats) {
  const std::string path = music_show(R"(
[[behavior]]
kind = "breathe"
target = "handle.head"
depth = [0.0, -10.0]
period = 1
sync = "beat"
)");
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  auto s = LiveShow::load(path, o);
  ASSERT_TRUE(s.ok()) << s.error;
  LiveShow& show = **s.value;
  const int head = show.mapping().handle_index("head");
  const double rest_y = show.mapping().targets()[size_t(head)].y();
  double worst = 0;
  int checked = 0;
  for (long f = 0; f < 120 * 6; ++f) {
    const double t = double(f) / 120;
    show.frame(int64_t(std::llround(t * 1e9)));
    if (t < 2.0 || t > 6.0) continue;  // locked after the clock's first beats
    // The clock's beat k is at 0.5 + 0.5 k s: the breath rests on each beat, tops between.
    const double beats = (t - 0.5) * 2;
    const double want = -10 * 0.5 * (1 - std::cos(2 * M_PI * beats));
    worst = std::max(worst, std::abs(show.targets()[size_t(head)].y() - rest_y - want));
    ++checked;
  }
  EXPECT_GT(checked, 400);
  // 0.32 units is 5 ms of the beat at the breath's steepest (10 x pi units a beat at 120 BPM).
  EXPECT_LT(worst, 0.32);
  const auto j = nlohmann::json::parse(show.stats_json());
  EXPECT_NEAR(j["music"]["bpm"].get<double>(), 120, 0.1);
}

TEST(LiveMusic, ASyncValueMustBeBeatOrTime) {
  const std::string path = music_show(R"(
[[behavior]]
kind = "breathe"
target = "handle.head"
sync = "bar"
)");
  const std::string err = LiveShow::validate(path);
  EXPECT_NE(err.find("music.toml:15: sync must be \"beat\" or \"time\""), std::string::npos) << err;
  const std::string physics = music_show("[physics]\nsync = \"beats\"\n");
  EXPECT_NE(LiveShow::validate(physics).find("sync must be \"beat\" or \"time\""), std::string::npos);
}

}  // namespace
}  // namespace mar
