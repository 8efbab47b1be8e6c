#include "app/loop/run_stats.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

TEST(RunHash, FollowsEveryVertexOfEveryFrame) {
  const std::vector<Points> a = {{Vec2(1, 2), Vec2(3, 4)}, {Vec2(5, 6)}};
  std::vector<Points> b = a;
  b[1][0].y() += 1e-12;  // the smallest visible change still changes the hash
  RunHash ha, hb, hc;
  ha.add(a);
  hb.add(b);
  EXPECT_NE(ha.value(), hb.value());
  hc.add(a);
  EXPECT_EQ(ha.value(), hc.value());
  ha.add(a);  // a second frame
  EXPECT_NE(ha.value(), hc.value());
}

TEST(RunStats, CountsOverrunsAndIterations) {
  RunStats s;
  s.end_frame(1000, 16666, 8);
  s.end_frame(20000, 16666, 6);
  s.end_frame(2000, 16666, 7);
  EXPECT_EQ(s.frames, 3);
  EXPECT_EQ(s.overruns, 1);
  EXPECT_EQ(s.iter_min, 6);
  EXPECT_EQ(s.iter_max, 8);
  EXPECT_DOUBLE_EQ(s.iter_mean(), 7.0);
  EXPECT_EQ(s.frame.max(), 20000);
}

TEST(Stage, TheFrameRunsTheDesignsStagesInOrder) {
  const char* want[] = {"inputs", "map", "poses", "motion", "solve", "render", "present"};
  ASSERT_EQ(size_t(Stage::Count), std::size(want));
  for (size_t k = 0; k < std::size(want); ++k) EXPECT_STREQ(stage_name(Stage(k)), want[k]);
}

}  // namespace
}  // namespace mar
