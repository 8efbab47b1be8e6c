// --dump-poses: every frame's shapes as JSON lines, formatted off the frame thread. What is
// pushed is what is read back (ids in the loader's order, points to 1e-3), nothing is dropped
// on the virtual clock, a full ring drops and counts on the wall clock, pushing allocates
// nothing, and a file that cannot be written is refused with its name. A run and its replay
// write the same file.
#include "alloc_counter.h"
#include "character/load.h"
#include "output/pose_dump.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>

namespace mar {
namespace {

Character two_shapes() {
  Character ch;
  SubShape a, b;
  a.id = "arm \"left\"";
  a.points = {{0, 0}, {10, 0}, {10, 5}};
  b.id = "tail";
  b.points = {{1, 1}, {2, 2}};
  ch.shapes = {a, b};
  return ch;
}

TEST(PoseDump, WritesWhatIsPushedOneLineAFrame) {
  const Character ch = two_shapes();
  const std::string path = (test::temp_dir("poses") / "a.jsonl").string();
  std::vector<Points> shapes = {ch.shapes[0].points, ch.shapes[1].points};
  {
    auto d = PoseDump::open(path, ch, true, 4);  // a small ring: the frame thread waits for room
    ASSERT_TRUE(d.ok()) << d.error;
    std::vector<char> shown = {1, 1};
    const long before = test::allocation_count();
    for (int f = 0; f < 500; ++f) {
      shapes[0][1] = Vec2(10 + f * 0.001, f);
      shown[1] = char(f % 3 != 0);  // the tail hidden every third frame (a swap member not chosen)
      if (f < 250) (*d.value)->push(f / 60.0, shapes, shown);
      else (*d.value)->push(f / 60.0, shapes);  // no mask: every shape shows
    }
    EXPECT_EQ(test::allocation_count() - before, 0) << "push allocates nothing";
    (*d.value)->flush();
    EXPECT_EQ((*d.value)->written(), 500u);
    EXPECT_EQ((*d.value)->dropped(), 0u);
  }
  std::ifstream in(path);
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    const auto j = nlohmann::json::parse(line);
    EXPECT_NEAR(j["t"].get<double>(), n / 60.0, 1e-6);
    ASSERT_EQ(j["subshapes"].size(), 2u);
    EXPECT_EQ(j["subshapes"][0]["id"], "arm \"left\"");
    EXPECT_EQ(j["subshapes"][1]["id"], "tail");
    ASSERT_EQ(j["subshapes"][0]["points"].size(), 3u);
    EXPECT_NEAR(j["subshapes"][0]["points"][1][0].get<double>(), 10 + n * 0.001, 1e-3);
    EXPECT_NEAR(j["subshapes"][0]["points"][1][1].get<double>(), n, 1e-3);
    EXPECT_FALSE(j["subshapes"][0].contains("shown"));
    EXPECT_EQ(j["subshapes"][1].contains("shown"), n < 250 && n % 3 == 0) << n;
    if (j["subshapes"][1].contains("shown")) {
      EXPECT_EQ(j["subshapes"][1]["shown"], false);
    }
    ++n;
  }
  EXPECT_EQ(n, 500);
}

TEST(PoseDump, OnTheWallClockAFullRingDropsAndCounts) {
  const Character ch = two_shapes();
  const std::string path = (test::temp_dir("poses") / "b.jsonl").string();
  std::vector<Points> shapes = {ch.shapes[0].points, ch.shapes[1].points};
  auto d = PoseDump::open(path, ch, false, 2);
  ASSERT_TRUE(d.ok()) << d.error;
  for (int f = 0; f < 20000; ++f) (*d.value)->push(f, shapes);  // faster than any disk
  (*d.value)->flush();
  EXPECT_EQ((*d.value)->written() + (*d.value)->dropped(), 20000u);
  EXPECT_EQ((*d.value)->waits(), 0u) << "the show never waits";
}

TEST(PoseDump, AFileThatCannotBeWrittenIsNamed) {
  auto d = PoseDump::open("/nonexistent-dir/p.jsonl", two_shapes(), true);
  ASSERT_FALSE(d.ok());
  EXPECT_NE(d.error.find("/nonexistent-dir/p.jsonl"), std::string::npos) << d.error;
  if (std::filesystem::exists("/dev/full")) {  // the disk fills: said, and the show goes on
    auto f = PoseDump::open("/dev/full", two_shapes(), true, 2);
    ASSERT_TRUE(f.ok()) << f.error;
    const Character ch = two_shapes();
    std::vector<Points> shapes = {ch.shapes[0].points, ch.shapes[1].points};
    for (int i = 0; i < 100000; ++i) (*f.value)->push(i, shapes);
    (*f.value)->flush();
    EXPECT_NE((*f.value)->error().find("/dev/full: No space left on device"), std::string::npos) << (*f.value)->error();
  }
}

// Coordinates at any magnitude are written in full (a 64-byte buffer once cut 1e308 short and
// left invalid JSON); a point that is not finite is [null, null].
TEST(PoseDump, NumbersAtAnyMagnitudeAreWrittenInFull) {
  Character ch = two_shapes();
  const std::string path = (test::temp_dir("poses-big") / "big.jsonl").string();
  {
    auto d = PoseDump::open(path, ch, true);
    ASSERT_TRUE(d.ok()) << d.error;
    std::vector<Points> shapes = {{{1e308, -1.7e308}, {-1e-300, 5}, {NAN, 1}}, {{1, 2}, {INFINITY, 3}}};
    (*d.value)->push(1e300, shapes);
    (*d.value)->flush();
    EXPECT_EQ((*d.value)->error(), "");
  }
  std::ifstream in(path);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  const auto j = nlohmann::json::parse(line, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << line.substr(0, 200);
  EXPECT_DOUBLE_EQ(j["subshapes"][0]["points"][0][0].get<double>(), 1e308);
  EXPECT_DOUBLE_EQ(j["subshapes"][0]["points"][0][1].get<double>(), -1.7e308);
  EXPECT_TRUE(j["subshapes"][0]["points"][2][0].is_null());
  EXPECT_TRUE(j["subshapes"][1]["points"][1][1].is_null());
  EXPECT_DOUBLE_EQ(j["t"].get<double>(), 1e300);
}

TEST(PoseDump, ARunAndItsReplayWriteTheSamePoses) {
  const auto dir = test::temp_dir("poses_cli");
  const std::string show = (test::source_dir() / "config/shows/demo.toml").string();
  auto live = test::run_cli("run " + show + " --headless --frames 150 --record " + (dir / "d.rec").string() + " --dump-poses " +
                            (dir / "live.jsonl").string());
  ASSERT_EQ(live.exit_code, 0) << live.err;
  auto rep = test::run_cli("replay " + (dir / "d.rec").string() + " --show " + show + " --dump-poses " + (dir / "replay.jsonl").string());
  ASSERT_EQ(rep.exit_code, 0) << rep.err;
  std::ifstream a(dir / "live.jsonl"), b(dir / "replay.jsonl");
  std::stringstream sa, sb;
  sa << a.rdbuf();
  sb << b.rdbuf();
  const std::string ta = sa.str(), tb = sb.str();
  EXPECT_EQ(std::count(ta.begin(), ta.end(), '\n'), 150);
  EXPECT_TRUE(ta == tb) << "the replay's poses differ from the run's";
  EXPECT_NE(live.out.find("150 poses written to"), std::string::npos) << live.out;
}

}  // namespace
}  // namespace mar
