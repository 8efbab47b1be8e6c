// The attract loop in a live show (tests/data/shows/attract.toml): it starts after the idle
// time, plays its script exactly as the same script on the device would, hands over to the
// visitor's first input with a crossfade that has no jump, and leaves no trace afterwards.
#include "app/live.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>

namespace mar {
namespace {

constexpr int kFrames = 660;  // 11 s at 60 Hz

struct Frame {
  AttractClock::State state = AttractClock::State::Live;
  double weight = 0;
  std::vector<Vec2> targets, live, attract;  ///< what the solver got; the two mappings' own
  bool mouth_e = false;
};

std::string attract_show_text() {
  std::ifstream in(test::source_dir() / "tests/data/shows/attract.toml");
  std::stringstream ss;
  ss << in.rdbuf();
  // Variants are written elsewhere: the rig by its absolute path.
  std::string text = ss.str();
  const std::string rel = "../../../config/rigs/singer.toml";
  text.replace(text.find(rel), rel.size(), (test::source_dir() / "config/rigs/singer.toml").string());
  return text;
}

std::vector<Frame> run_frames(const std::string& path) {
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  auto s = LiveShow::load(path, o);
  EXPECT_TRUE(s.ok()) << s.error;
  std::vector<Frame> out;
  if (!s.ok()) return out;
  LiveShow& show = **s.value;
  size_t mouth_e = 0;
  for (size_t k = 0; k < show.puppet().character.shapes.size(); ++k)
    if (show.puppet().character.shapes[k].id == "mouth-e") mouth_e = k;
  for (int f = 0; f < kFrames; ++f) {
    show.frame(int64_t(f * 1e9 / 60));
    Frame fr;
    // The performer's targets: a [[physics]] chain's ends are the motion stage's, which carries
    // on swinging from whatever moved it (a trace of motion, not of the attract's mapping).
    const auto t = show.targets();
    for (size_t h = 0; h < t.size(); ++h) {
      bool chain = false;
      for (const PuppetChain& c : show.puppet().chains) chain = chain || std::find(c.handles.begin(), c.handles.end(), h) != c.handles.end();
      if (!chain) fr.targets.push_back(t[h]);
    }
    const auto live = show.mapping().targets();
    fr.live.assign(live.begin(), live.end());
    if (const Attract* a = show.attract()) {
      fr.state = a->state();
      fr.weight = a->weight();
      const auto at = a->mapping().targets();
      fr.attract.assign(at.begin(), at.end());
    }
    fr.mouth_e = show.puppet().shown[mouth_e];
    out.push_back(std::move(fr));
  }
  const auto j = nlohmann::json::parse(show.stats_json());
  if (show.attract()) {
    EXPECT_EQ(j["attract"]["starts"], 1);
    EXPECT_EQ(j["attract"]["handovers"], 1);
  }
  return out;
}

double max_diff(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  double d = 0;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) d = std::max(d, (a[i] - b[i]).norm());
  return d;
}

TEST(LiveAttract, PlaysWhenIdleHandsOverWithoutAJumpAndLeavesNoTrace) {
  const std::string text = attract_show_text();
  const std::string with = test::write_temp("attract.toml", text);
  // The visitor alone: the same show without [attract].
  const size_t a0 = text.find("[attract]"), a1 = text.find("[[binding]]");
  ASSERT_NE(a0, std::string::npos);
  const std::string visitor = test::write_temp("visitor.toml", text.substr(0, a0) + text.substr(a1));
  // The attract's script alone, as the device's own script from time 0.
  const size_t s0 = text.find("script = \"\"\"", a0);
  const std::string attract_script = text.substr(s0, text.find("\"\"\"", s0 + 12) + 3 - s0);
  const size_t d0 = text.find("script = \"\"\"");
  std::string alone_text = text.substr(0, d0) + attract_script + text.substr(text.find("\"\"\"", d0 + 12) + 3, a0 - (text.find("\"\"\"", d0 + 12) + 3)) + text.substr(a1);
  const std::string alone = test::write_temp("alone.toml", alone_text);

  const std::vector<Frame> f = run_frames(with), v = run_frames(visitor), s = run_frames(alone);
  ASSERT_EQ(f.size(), size_t(kFrames));
  ASSERT_EQ(v.size(), size_t(kFrames));
  ASSERT_EQ(s.size(), size_t(kFrames));

  // Live -> FadeIn -> Playing -> FadeOut -> Live, once.
  using S = AttractClock::State;
  int start = -1, playing = -1, handover = -1, live_again = -1;
  for (int k = 1; k < kFrames; ++k) {
    if (f[k].state != f[k - 1].state) {
      if (f[k].state == S::FadeIn && start < 0) start = k;
      else if (f[k].state == S::Playing && playing < 0) playing = k;
      else if (f[k].state == S::FadeOut && handover < 0) handover = k;
      else if (f[k].state == S::Live && live_again < 0) live_again = k;
      else ADD_FAILURE() << "unexpected state change at frame " << k;
    }
  }
  // The visitor's fader stops at 0.6 s: the attract starts 2 s later, fades in over 0.5 s
  // (30 frames), and the visitor's fader at 9.0 s hands over, again over 0.5 s.
  EXPECT_GE(start, 155);
  EXPECT_LE(start, 158);
  EXPECT_EQ(playing - start, 29);
  EXPECT_GE(handover, 540);
  EXPECT_LE(handover, 541);
  EXPECT_EQ(live_again - handover, 29);

  // Before it starts and once it has faded out, the show is exactly the visitor's.
  for (int k = 0; k < start; ++k) ASSERT_LT(max_diff(f[k].targets, v[k].targets), 1e-9) << "frame " << k;
  for (int k = live_again; k < kFrames; ++k) ASSERT_LT(max_diff(f[k].targets, v[k].targets), 1e-9) << "frame " << k;
  // While it plays, the character is exactly what the script alone makes, from the script's start
  // (the attract's frame n plays n + 1 frames of its script), and again from the start after
  // its 4.5 s loop.
  int compared = 0;
  for (int k = playing; k < handover; ++k) {
    const int n = (k - start + 1) % 270;
    if (n == 0) continue;  // the loop's seam: the last and first records in one frame
    ASSERT_LT(max_diff(f[k].targets, s[n].targets), 1e-9) << "frame " << k << " = script frame " << n;
    ++compared;
  }
  EXPECT_GT(compared, 300);
  // The crossfades: the two sides differ by a lot, and no frame steps more than a fraction of it
  // (a cut would step the whole gap).
  const double gap_in = max_diff(f[start].live, f[start].attract);
  const double gap_out = max_diff(f[handover].live, f[handover].attract);
  EXPECT_GT(gap_in, 30.0);
  EXPECT_GT(gap_out, 30.0);
  double step_in = 0, step_out = 0;
  for (int k = start; k <= playing; ++k) step_in = std::max(step_in, max_diff(f[k].targets, f[k - 1].targets));
  for (int k = handover; k <= live_again; ++k) step_out = std::max(step_out, max_diff(f[k].targets, f[k - 1].targets));
  std::printf("[ measure ] attract: starts at frame %d, hands over at %d; largest step %.1f / %.1f units against "
              "gaps of %.1f / %.1f\n", start, handover, step_in, step_out, gap_in, gap_out);
  EXPECT_LT(step_in, 0.15 * gap_in) << "gap " << gap_in;
  EXPECT_LT(step_out, 0.15 * gap_out) << "gap " << gap_out;
  // The attract's mouth (S 3 at 0.4 s of its script) shows while the attract is the stronger
  // side, and the visitor's smile comes back with the visitor.
  EXPECT_FALSE(f[start - 1].mouth_e);
  EXPECT_TRUE(f[start + 40].mouth_e);
  EXPECT_TRUE(f[handover - 1].mouth_e);
  EXPECT_FALSE(f[live_again].mouth_e);
}

// A take recorded from a show (`run --record`) plays in the attract as it was recorded.
TEST(LiveAttract, ATakeRecordedFromTheShowPlaysAsItWasRecorded) {
  const std::string text = attract_show_text();
  const size_t a0 = text.find("[attract]"), a1 = text.find("[[binding]]");
  const size_t s0 = text.find("script = \"\"\"", a0);
  const std::string attract_script = text.substr(s0, text.find("\"\"\"", s0 + 12) + 3 - s0);
  const size_t d0 = text.find("script = \"\"\""), d1 = text.find("\"\"\"", d0 + 12) + 3;
  const std::string alone = test::write_temp("take_alone.toml", text.substr(0, d0) + attract_script +
                                                                     text.substr(d1, a0 - d1) + text.substr(a1));
  const std::string take = (test::temp_dir("attract") / "idle.marrec").string();
  {
    RunOptions o;
    o.headless = true;
    o.quiet = true;
    o.frames = 270;
    o.record_path = take;
    auto rec = LiveShow::load(alone, o);
    ASSERT_TRUE(rec.ok()) << rec.error;
    ASSERT_EQ((*rec.value)->run(), 0);
  }
  const std::string with_take = test::write_temp(
      "take.toml", text.substr(0, a0) + "[attract]\nafter = 2\nfade = 0.5\ntake = \"" + take + "\"\n\n" + text.substr(a1));
  const std::vector<Frame> f = run_frames(with_take), s = run_frames(alone);
  ASSERT_EQ(f.size(), size_t(kFrames));
  int start = -1, compared = 0;
  for (int k = 1; k < kFrames; ++k) {
    if (start < 0 && f[k].state == AttractClock::State::FadeIn) start = k;
    if (start < 0 || f[k].state != AttractClock::State::Playing) continue;
    const int n = k - start + 1;
    if (n >= 260) break;  // the take is 270 frames long and loops
    ASSERT_LT(max_diff(f[k].targets, s[n].targets), 1e-9) << "frame " << k << " = take frame " << n;
    ++compared;
  }
  EXPECT_GT(compared, 200);
  // Not a recording: refused with the show's [attract] line.
  const std::string junk = test::write_temp("junk.marrec", "not a recording");
  const std::string bad = test::write_temp(
      "bad_take.toml", text.substr(0, a0) + "[attract]\nafter = 2\ntake = \"" + junk + "\"\n\n" + text.substr(a1));
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  auto r = LiveShow::load(bad, o);
  ASSERT_FALSE(r.ok());
  const int line = int(std::count(text.begin(), text.begin() + long(a0), '\n')) + 1;
  EXPECT_NE(r.error.find("bad_take.toml:" + std::to_string(line) + ": [attract]: "), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("junk.marrec"), std::string::npos) << r.error;
  EXPECT_EQ(LiveShow::validate(bad), r.error);  // a reload checks the take too
}

TEST(LiveAttract, BadAttractTablesNameFileAndLine) {
  const std::string text = attract_show_text();
  const size_t a0 = text.find("[attract]");
  const auto variant = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    t.replace(t.find(from, a0), from.size(), to);
    return test::write_temp("bad_attract.toml", t);
  };
  const auto error_of = [](const std::string& path) {
    RunOptions o;
    o.headless = true;
    o.quiet = true;
    auto s = LiveShow::load(path, o);
    EXPECT_FALSE(s.ok()) << path;
    EXPECT_EQ(LiveShow::validate(path), s.error);  // what SIGHUP checks before a reload
    return s.error;
  };
  // A bad script line: the file's own line number.
  const int bad_line = int(std::count(text.begin(), text.begin() + long(text.find("0.4 press solo3", a0)), '\n')) + 1;
  const std::string e1 = error_of(variant("0.4 press solo3 for 0.1", "0.4 press nothing9 for 0.1"));
  EXPECT_NE(e1.find("bad_attract.toml:" + std::to_string(bad_line) + ":"), std::string::npos) << e1;
  const std::string e2 = error_of(variant("device = \"korg\"", "device = \"nobody\""));
  EXPECT_NE(e2.find("no [[device]] named 'nobody'"), std::string::npos) << e2;
  const std::string e3 = error_of(variant("after = 2", "after = 0.1"));
  EXPECT_NE(e3.find("after must be 1..86400 s"), std::string::npos) << e3;
  const std::string e4 = error_of(variant("loop = 4.5", "take = \"x.marrec\""));
  EXPECT_NE(e4.find("one of script, script_file (with device) or take"), std::string::npos) << e4;
  const std::string e5 = error_of(variant("fade = 0.5", "fade = 0.5\ncolour = 3"));
  EXPECT_NE(e5.find("colour"), std::string::npos) << e5;
}

}  // namespace
}  // namespace mar
