// Pendulum and spring chains at a fixed step: the physics (a small-angle pendulum's period,
// a spring's frequency, the damping's decay per cycle), the same motion whatever the frame
// rate, resets, mix, and what random jerks and bad input cannot do (non-finite states, speeds
// past the limit, allocations).
#include "alloc_counter.h"
#include "motion/chain.h"
#include "chain_measure.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace mar {
namespace {

constexpr double kH = measure::kStep;

TEST(Chain, ASmallAnglePendulumSwingsWithItsPeriod) {
  const double L = 100, g = 980;
  const double want = 2 * M_PI * std::sqrt(L / g), got = measure::pendulum_period(L, g);
  std::cout << "pendulum period " << got << " s, 2 pi sqrt(L/g) = " << want << " s" << std::endl;
  EXPECT_NEAR(got, want, 0.03 * want);
}

TEST(Chain, ASpringOscillatesAtItsFrequencyAngleAndLength) {
  const double angle = measure::spring_frequency(2), length = measure::spring_length_frequency(3);
  std::cout << "angular spring " << angle << " Hz (set 2 Hz), spring length " << length << " Hz (set 3 Hz)" << std::endl;
  EXPECT_NEAR(angle, 2.0, 0.03 * 2.0);
  EXPECT_NEAR(length, 3.0, 0.03 * 3.0);
}

TEST(Chain, AmplitudeDecaysByTheDampingsFactorPerCycle) {
  for (double zeta : {0.05, 0.1, 0.2}) {
    const double want = std::exp(-2 * M_PI * zeta / std::sqrt(1 - zeta * zeta)), got = measure::decay_per_cycle(zeta);
    std::cout << "damping " << zeta << ": amplitude x" << got << " per cycle (theory " << want << ")" << std::endl;
    EXPECT_NEAR(got, want, 0.05 * want);
  }
}

// The parent sways and turns; the chain's ends at common times are the same whatever the
// frame rate (RMS difference <= 1% of the chain's length).
TEST(Chain, TheSameMotionAtThirtySixtyAndHundredFortyFourAndTwoFortyHz) {
  for (int rate : {144, 60, 30}) {
    const double pct = measure::frame_rate_rms_pct(rate);
    std::cout << "rate " << rate << " Hz vs 240 Hz: RMS " << pct << "% of the chain's length" << std::endl;
    EXPECT_LE(pct, 1.0);
  }
}

// A spring chain drawn sideways rests as drawn under gravity while its parent is as drawn; the
// parent turned upside down, gravity pulls it the other way (it does not just turn with it).
TEST(Chain, ASpringChainSettlesAsDrawnAndGravityPullsWhenTheParentTurns) {
  ChainParams p;
  p.frequency = 2;
  p.damping = 0.3;
  const Vec2 rest[] = {{0, 0}, {60, 0}, {120, 10}};
  Chain c(rest, p);
  MotionWorld w;
  w.gravity = {0, 980};
  for (int f = 0; f < 600; ++f) c.advance(1.0 / 60, kH, {0, 0}, 0, w);
  EXPECT_LT((c.ends()[1] - Vec2(120, 10)).norm(), 0.05) << "still where it was drawn";
  for (int f = 0; f < 600; ++f) c.advance(1.0 / 60, kH, {0, 0}, M_PI, w);
  // Rigidly turned, the end would be at (-120, -10); gravity pulls it down from there.
  EXPECT_GT(c.ends()[1].y(), -10 + 20) << "it sags toward the ground";
}

TEST(Chain, AStallOrAResetPutsItAtRestStill) {
  ChainParams p;
  p.frequency = 1;
  const Vec2 rest[] = {{0, 0}, {0, 50}, {0, 100}};
  Chain c(rest, p);
  MotionWorld w;
  for (int f = 0; f < 30; ++f) c.advance(1.0 / 60, kH, {f * 5.0, 0}, 0, w);
  EXPECT_GT(std::abs(c.ends()[1].x() - 145), 1.0) << "it lags behind the moving parent";
  const long before = c.resets();
  c.advance(0.3, kH, {200, 0}, M_PI / 2, w);  // a stall: at rest, turned with the parent
  EXPECT_EQ(c.resets(), before + 1);
  EXPECT_NEAR(c.ends()[1].x(), 100, 1e-9);
  EXPECT_NEAR(c.ends()[1].y(), 0, 1e-9);
  c.advance(1.0 / 60, kH, {200, 0}, M_PI / 2, w);
  EXPECT_NEAR(c.ends()[1].x(), 100, 1e-6) << "and still";
}

TEST(Chain, MixZeroFollowsTheParentRigidly) {
  ChainParams p;
  p.mix = 0;
  const Vec2 rest[] = {{0, 0}, {0, 50}, {20, 90}};
  Chain c(rest, p);
  MotionWorld w;
  w.gravity = {0, 980};
  for (int f = 1; f <= 100; ++f) {
    const double rot = 0.01 * f;
    const Vec2 a(3.0 * f, -2.0 * f);
    c.advance(1.0 / 60, kH, a, rot, w);
    const Vec2 want = a + Vec2(std::cos(rot) * 20 - std::sin(rot) * 90, std::sin(rot) * 20 + std::cos(rot) * 90);
    ASSERT_LT((c.ends()[1] - want).norm(), 1e-9);
  }
  c.params().mix = 1;
  w.strength = 0;  // the world's master control does the same
  c.advance(1.0 / 60, kH, {300, -200}, 1.0, w);
  EXPECT_LT((c.ends()[1] - (Vec2(300, -200) + Vec2(std::cos(1.0) * 20 - std::sin(1.0) * 90, std::sin(1.0) * 20 + std::cos(1.0) * 90))).norm(),
            1e-9);
}

// 10^6 random parent jerks (and bad frames) per model: every end finite, no link end faster
// than the limit, no allocation.
TEST(Chain, RandomJerksStayFiniteAndWithinTheLimit) {
  for (ChainParams::Model model : {ChainParams::Pendulum, ChainParams::Spring}) {
    const measure::Jerks j = measure::random_jerks(model, 1000000, &test::allocation_count);
    EXPECT_EQ(j.allocations, 0) << "advance allocates nothing";
    EXPECT_EQ(j.bad, 0);
    std::cout << (model == ChainParams::Spring ? "spring" : "pendulum") << ": fastest link end " << j.fastest << " units/s (limit 900), "
              << j.resets << " resets, " << j.reverts << " reverted steps" << std::endl;
    EXPECT_LE(j.fastest, 900 * 1.001);
  }
}

TEST(Chain, WindNoiseIsSmoothBoundedAndTheSameEachTime) {
  double last = smooth_noise(0, 3), worst_step = 0;
  for (int i = 1; i < 100000; ++i) {
    const double v = smooth_noise(i * 0.001, 3);
    ASSERT_LE(std::abs(v), 1.0);
    worst_step = std::max(worst_step, std::abs(v - last));
    last = v;
  }
  EXPECT_LT(worst_step, 0.01) << "smooth: 1 ms moves it by less than 1%";
  EXPECT_EQ(smooth_noise(12.5, 3), smooth_noise(12.5, 3));
  EXPECT_NE(smooth_noise(12.5, 3), smooth_noise(12.5, 4));
}

}  // namespace
}  // namespace mar
