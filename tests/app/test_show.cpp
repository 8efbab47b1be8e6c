// Show files are parsed once, from default_show(), and resolved against the rig the
// [show] table names (handles, and the settings the loop and the solver offer).
#include "app/show.h"
#include "test_util.h"

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
