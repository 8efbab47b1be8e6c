// The show's idle behaviours: [[behavior]] tables read and refused with file and line; a blink
// shows over the mapping's triggers and swaps; a performer's control on a behaviour's target
// pauses it; and in a running show the singer blinks, breathes and looks about, the same on
// every run, allocating nothing after warm-up.
#include "app/live.h"
#include "app/loop/idle.h"
#include "app/show.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>

namespace mar {
namespace {

ShowRig rig_with_trigger() {
  ShowRig r;
  r.handles = {"head", "chest"};
  r.rest = {Vec2(0, 0), Vec2(0, 50)};
  r.diag = 100;
  r.settings = {{"iterations", std::pair<double, double>(3, 9)}, {"blend.sway", std::pair<double, double>(0, 1)}};
  r.swaps = {{"eyes", {"open", "shut"}}};
  r.triggers = {"blink"};
  return r;
}

const char* kHead = R"([show]
rig = "r.toml"
[[device]]
name = "k"
sim = "nanokontrol2"
[[binding]]
device = "k"
control = "cc 0"
target = "handle.chest.y"
)";

TEST(IdleShow, BehaviorsAreReadAndBadOnesRefusedWithFileAndLine) {
  auto ok = load_show(test::write_temp("idle-ok.toml", std::string(kHead) + R"(
[[behavior]]
kind = "blink"
target = "swap.eyes.shut"
mean = 3
[[behavior]]
kind = "breathe"
target = "handle.chest"
depth = [0, -2]
[[behavior]]
kind = "sway"
target = "blend.sway"
range = 0.4
)"),
                      [](const ShowConfig&) { return Result<ShowRig>::success(rig_with_trigger()); });
  ASSERT_TRUE(ok.ok()) << ok.error;
  ASSERT_EQ(ok.value->behaviors.size(), 3u);
  EXPECT_EQ(ok.value->behaviors[0].target, TargetKind::Swap);
  EXPECT_EQ(ok.value->behaviors[0].member, 1);
  EXPECT_EQ(ok.value->behaviors[1].spec.depth, Vec2(0, -2));
  EXPECT_EQ(ok.value->behaviors[2].spec.kind, BehaviorSpec::Look);
  EXPECT_DOUBLE_EQ(ok.value->behaviors[2].spec.amount, 0.4);
  struct Case {
    const char* toml;
    const char* says;
  } cases[] = {
      {"[[behavior]]\nkind = \"wink\"\ntarget = \"trigger.blink\"\n", ":12: kind must be blink, breathe, look or sway"},
      {"[[behavior]]\nkind = \"blink\"\ntarget = \"handle.head\"\n", ":13: a blink shows something"},
      {"[[behavior]]\nkind = \"breathe\"\ntarget = \"trigger.blink\"\n", ":13: breathe moves something"},
      {"[[behavior]]\nkind = \"look\"\ntarget = \"handle.head\"\ndepth = [1, 2]\n", ":14: depth is for breathe"},
      {"[[behavior]]\nkind = \"blink\"\ntarget = \"trigger.wink\"\n", ":13: no trigger 'wink'"},
      {"[[behavior]]\nkind = \"blink\"\ntarget = \"trigger.blink\"\nmean = 0\n", ":14: mean must be 0.1..3600"},
      {"[[behavior]]\nkind = \"blink\"\n", ":11: behavior 'blink' needs a target"},
      {"[[behavior]]\nkind = \"blink\"\ntarget = \"trigger.blink\"\nmood = 1\n", ":14: unknown key 'mood' in [[behavior]]"},
  };
  for (const Case& c : cases) {
    const std::string path = test::write_temp("idle-bad.toml", std::string(kHead) + "\n" + c.toml);
    auto r = load_show(path, [](const ShowConfig&) { return Result<ShowRig>::success(rig_with_trigger()); });
    ASSERT_FALSE(r.ok()) << c.toml;
    EXPECT_NE(r.error.find(path + c.says), std::string::npos) << r.error;
  }
}

TEST(IdleStage, ABlinkShowsOverTheMappingAndAControlPausesItsBehavior) {
  auto show = load_show(test::write_temp("idle-stage.toml", std::string(kHead) + R"(
[[behavior]]
kind = "blink"
target = "trigger.blink"
mean = 0.5
jitter = 0
hold = 0.1
[[behavior]]
kind = "breathe"
target = "handle.chest"
depth = [0, -4]
period = 2
resume = 1
fade = 0
)"),
                        [](const ShowConfig&) { return Result<ShowRig>::success(rig_with_trigger()); });
  ASSERT_TRUE(show.ok()) << show.error;
  Mapping m;
  m.set_handles({"head", "chest"}, {Vec2(0, 0), Vec2(0, 50)});
  for (const Binding& b : show.value->bindings) m.add_binding(b);
  IdleStage idle;
  idle.prepare(*show.value, m);
  ASSERT_TRUE(idle.has_blinks());
  const std::vector<int> members{0};
  const std::vector<char> triggers{0};
  bool blinked = false;
  for (int f = 0; f < 60; ++f) {
    idle.step(1.0 / 60, m);
    idle.shown(members, triggers);
    blinked = blinked || idle.triggers()[0];
  }
  EXPECT_TRUE(blinked) << "a blink turned the trigger on";
  // Breathing moves the chest; a fader on the chest pauses it, and it comes back a second after.
  std::vector<Vec2> t{Vec2(0, 0), Vec2(0, 50)};
  idle.apply_targets(t, {}, {});
  EXPECT_NE(t[1].y(), 50.0);
  Event e;
  e.source = 0;
  e.kind = ControlKind::MidiCC;
  e.number = 0;
  e.value = 64;
  ASSERT_TRUE(m.apply(e));
  idle.step(1.0 / 60, m);
  t = {Vec2(0, 0), Vec2(0, 50)};
  idle.apply_targets(t, {}, {});
  EXPECT_EQ(t[1], Vec2(0, 50)) << "paused while the fader moves the chest";
  for (int f = 0; f < 61; ++f) idle.step(1.0 / 60, m);
  t = {Vec2(0, 0), Vec2(0, 50)};
  idle.apply_targets(t, {}, {});
  EXPECT_NE(t[1], Vec2(0, 50)) << "and back a second after";
}

TEST(IdleShow, TheSingerIsAliveTheSameOnEveryRun) {
  const std::string show = (test::source_dir() / "config/shows/idle.toml").string();
  std::string hashes[2];
  for (int run = 0; run < 2; ++run) {
    const auto dir = test::temp_dir("idle_run" + std::to_string(run));
    auto r = test::run_cli("run " + show + " --headless --stats " + (dir / "s.json").string() + " --dump-poses " + (dir / "p.jsonl").string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::ifstream f(dir / "s.json");
    const auto j = nlohmann::json::parse(f);
    hashes[run] = j["run_hash"];
    EXPECT_EQ(j["heap_allocations_after_warmup"], 0);
    EXPECT_GE(j["behaviors"][0]["blinks"].get<int>(), 2) << "she blinks";
    // Nobody touches her for the first 4 s, and she moves: the chest breathes, the head turns.
    std::ifstream poses(dir / "p.jsonl");
    std::string line;
    std::vector<nlohmann::json> frames;
    while (std::getline(poses, line) && frames.size() < 230) frames.push_back(nlohmann::json::parse(line));
    ASSERT_EQ(frames.size(), 230u);
    auto point = [&](const nlohmann::json& fr, const char* id) {
      for (const auto& s : fr["subshapes"])
        if (s["id"] == id) return Vec2(s["points"][0][0].get<double>(), s["points"][0][1].get<double>());
      return Vec2(NAN, NAN);
    };
    double face = 0, dress = 0;
    for (const auto& fr : frames) {
      face = std::max(face, (point(fr, "face") - point(frames[0], "face")).norm());
      dress = std::max(dress, (point(fr, "dress") - point(frames[0], "dress")).norm());
    }
    std::cout << "idle, untouched for 3.8 s: the face moves up to " << face << " units, the dress " << dress << std::endl;
    EXPECT_GT(face, 2.0);
    EXPECT_GT(dress, 1.0);
  }
  EXPECT_EQ(hashes[0], hashes[1]);
}

}  // namespace
}  // namespace mar

namespace mar {
namespace {

// The voice show: a simulated microphone speaks (espeak-ng, at load) and its visemes pick the
// singer's mouth; the recording holds the PCM blocks, and a replay decodes them again to the
// same poses.
TEST(VoiceShow, TheSingerLipSyncsAndAReplayDecodesTheSameVoice) {
  if (std::system("command -v espeak-ng >/dev/null 2>&1") != 0) GTEST_SKIP() << "espeak-ng is not installed (Debian package espeak-ng)";
  const std::string show = (test::source_dir() / "config/shows/voice.toml").string();
  const auto dir = test::temp_dir("voice_show");
  auto live = test::run_cli("run " + show + " --headless --record " + (dir / "v.rec").string() + " --stats " + (dir / "live.json").string());
  ASSERT_EQ(live.exit_code, 0) << live.err;
  auto rep = test::run_cli("replay " + (dir / "v.rec").string() + " --show " + show + " --stats " + (dir / "replay.json").string());
  ASSERT_EQ(rep.exit_code, 0) << rep.err;
  std::ifstream a(dir / "live.json"), b(dir / "replay.json");
  const auto ja = nlohmann::json::parse(a), jb = nlohmann::json::parse(b);
  EXPECT_EQ(ja["run_hash"], jb["run_hash"]);
  EXPECT_GE(ja["events"]["mapped"].get<int>(), 20) << "the visemes pick mouths";
  EXPECT_EQ(ja["devices"][0]["malformed"], 0);
  EXPECT_EQ(ja["heap_allocations_after_warmup"], 0);
}

}  // namespace
}  // namespace mar
