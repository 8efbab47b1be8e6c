#include "app/loop/governor.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

TEST(Governor, DropsAnIterationAboveEightyPercentNeverBelowTheFloor) {
  Governor g(8, 3);
  EXPECT_EQ(g.next(8, 0.9 * 16, 16), 7);
  EXPECT_EQ(g.next(8, 0.9 * 16, 16), 6);
  for (int k = 0; k < 10; ++k) g.next(8, 20, 16);
  EXPECT_EQ(g.iterations(), 3);
  EXPECT_EQ(g.reductions(), 5);
}

TEST(Governor, GivesItBackBelowFortyPercentUpToWhatTheShowWants) {
  Governor g(8, 2);
  g.next(8, 15, 16);
  g.next(8, 15, 16);
  EXPECT_EQ(g.iterations(), 6);
  EXPECT_EQ(g.next(8, 8, 16), 6);  // between 40 and 80 %: holds
  EXPECT_EQ(g.next(8, 1, 16), 7);
  EXPECT_EQ(g.next(8, 1, 16), 8);
  EXPECT_EQ(g.next(8, 1, 16), 8);  // never above the ceiling
  EXPECT_EQ(g.next(5, 1, 16), 5);  // a lower ceiling (a knob) applies at once
}

TEST(Governor, AReplayedCountIsTakenAsIs) {
  Governor g(8, 2);
  g.force(4);
  EXPECT_EQ(g.iterations(), 4);
  EXPECT_EQ(g.reductions(), 0);
}

}  // namespace
}  // namespace mar
