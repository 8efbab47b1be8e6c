// The attract loop's idle timer and crossfade weight.
#include "app/loop/attract.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

using State = AttractClock::State;

TEST(AttractClock, StartsAfterIdleSecondsFadesInAndHandsOverOnInput) {
  AttractClock c(2.0, 0.5);
  const double dt = 0.125;  // exact in binary: the frame counts below are exact
  int f = 0;
  // Input every frame for 1.25 s keeps it away; then 2 s of nothing.
  for (; f < 10; ++f) EXPECT_FALSE(c.step(dt, true));
  int started = -1;
  for (; f < 60 && started < 0; ++f)
    if (c.step(dt, false)) started = f;
  EXPECT_EQ(started, 25);  // the 16th idle frame: 2.0 s without input
  EXPECT_EQ(c.state(), State::FadeIn);
  double last = c.weight();
  EXPECT_GT(last, 0.0);
  EXPECT_LT(last, 0.2);
  for (int k = 0; k < 3; ++k) {  // 0.5 s of fade in: four frames
    c.step(dt, false);
    EXPECT_GT(c.weight(), last);
    last = c.weight();
  }
  EXPECT_EQ(c.state(), State::Playing);
  EXPECT_DOUBLE_EQ(c.weight(), 1.0);
  for (int k = 0; k < 100; ++k) EXPECT_FALSE(c.step(dt, false));  // plays on, never restarts
  EXPECT_EQ(c.state(), State::Playing);
  // The first input hands over; the fade goes on without further input.
  c.step(dt, true);
  EXPECT_EQ(c.state(), State::FadeOut);
  last = c.weight();
  EXPECT_LT(last, 1.0);
  for (int k = 0; k < 3; ++k) {
    c.step(dt, false);
    EXPECT_LT(c.weight(), last);
    last = c.weight();
  }
  EXPECT_EQ(c.state(), State::Live);
  EXPECT_DOUBLE_EQ(c.weight(), 0.0);
  EXPECT_FALSE(c.shown());
  // Idle again counts from the input, not from the end of the fade.
  EXPECT_DOUBLE_EQ(c.idle_seconds(), 0.375);
}

TEST(AttractClock, InputDuringTheFadeInTurnsBackFromWhereItIs) {
  AttractClock c(1.0, 1.0);
  for (int f = 0; f < 8; ++f) c.step(0.125, false);
  ASSERT_EQ(c.state(), State::FadeIn);
  c.step(0.125, false);
  c.step(0.125, false);
  const double w = c.weight();
  c.step(0.125, true);
  EXPECT_EQ(c.state(), State::FadeOut);
  EXPECT_LT(c.weight(), w);
  EXPECT_GT(c.weight(), 0.0);  // no jump to the visitor
  int frames = 0;
  while (c.shown() && frames < 100) {
    c.step(0.125, false);
    ++frames;
  }
  EXPECT_EQ(frames, 2);  // back out in as long as it had faded in
}

TEST(AttractClock, NoFadeCutsAtOnce) {
  AttractClock c(1.0, 0.0);
  for (int f = 0; f < 7; ++f) EXPECT_FALSE(c.step(0.125, false));
  EXPECT_TRUE(c.step(0.125, false));
  EXPECT_EQ(c.state(), State::Playing);
  EXPECT_DOUBLE_EQ(c.weight(), 1.0);
  c.step(0.125, true);
  EXPECT_EQ(c.state(), State::Live);
  EXPECT_DOUBLE_EQ(c.weight(), 0.0);
}

}  // namespace
}  // namespace mar
