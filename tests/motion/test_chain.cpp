// Pendulum and spring chains at a fixed step: the physics (a small-angle pendulum's period,
// a spring's frequency, the damping's decay per cycle), the same motion whatever the frame
// rate, resets, mix, and what random jerks and bad input cannot do (non-finite states, speeds
// past the limit, allocations).
#include "alloc_counter.h"
#include "motion/chain.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace mar {
namespace {

constexpr double kH = 1.0 / 120;  // the default step

// Times where `x` crosses its mean going up, interpolated (from a sampled signal).
std::vector<double> upward_crossings(const std::vector<double>& t, const std::vector<double>& x, double mean) {
  std::vector<double> out;
  for (size_t i = 1; i < x.size(); ++i)
    if (x[i - 1] < mean && x[i] >= mean) out.push_back(t[i - 1] + (mean - x[i - 1]) / (x[i] - x[i - 1]) * (t[i] - t[i - 1]));
  return out;
}

double mean_period(const std::vector<double>& c) {
  return c.size() < 2 ? 0 : (c.back() - c.front()) / double(c.size() - 1);
}

TEST(Chain, ASmallAnglePendulumSwingsWithItsPeriod) {
  const double L = 100, g = 980;
  ChainParams p;
  p.damping = 0;
  const double a0 = 4 * M_PI / 180;  // drawn 4 degrees off the vertical: it swings by 4 degrees
  const Vec2 rest[] = {{0, 0}, {L * std::sin(a0), L * std::cos(a0)}};
  Chain c(rest, p);
  MotionWorld w;
  w.gravity = {0, g};
  std::vector<double> t, x;
  for (int f = 1; f <= 60 * 20; ++f) {  // 60 Hz frames for 20 s
    c.advance(1.0 / 60, kH, {0, 0}, 0, w);
    t.push_back(f / 60.0);
    x.push_back(c.ends()[0].x());
  }
  const double want = 2 * M_PI * std::sqrt(L / g);
  const double got = mean_period(upward_crossings(t, x, 0));
  std::cout << "pendulum period " << got << " s, 2 pi sqrt(L/g) = " << want << " s" << std::endl;
  EXPECT_NEAR(got, want, 0.03 * want);
}

TEST(Chain, ASpringOscillatesAtItsFrequencyAngleAndLength) {
  {  // the angular spring toward the drawn direction (no gravity)
    ChainParams p;
    p.frequency = 2;
    p.damping = 0;
    const Vec2 rest[] = {{0, 0}, {0, 80}};
    Chain c(rest, p);
    MotionWorld w;
    std::vector<double> t, x;
    for (int f = 0; f < 4; ++f) c.advance(1.0 / 60, kH, {0, 0}, 0, w);
    c.advance(1.0 / 60, kH, {6, 0}, 0, w);  // a jerk sideways, then still
    for (int f = 1; f <= 60 * 10; ++f) {
      c.advance(1.0 / 60, kH, {6, 0}, 0, w);
      t.push_back(f / 60.0);
      x.push_back(c.ends()[0].x() - 6);
    }
    const double got = 1 / mean_period(upward_crossings(t, x, 0));
    std::cout << "angular spring " << got << " Hz (set 2 Hz)" << std::endl;
    EXPECT_NEAR(got, 2.0, 0.03 * 2.0);
  }
  {  // the spring model's length: a jerk along the link, under gravity (drawn as it settles)
    ChainParams p;
    p.model = ChainParams::Spring;
    p.frequency = 3;
    p.damping = 0;
    const Vec2 rest[] = {{0, 0}, {0, 80}};
    Chain c(rest, p);
    MotionWorld w;
    w.gravity = {0, 400};
    std::vector<double> t, y;
    for (int f = 0; f < 4; ++f) c.advance(1.0 / 60, kH, {0, 0}, 0, w);
    EXPECT_NEAR(c.ends()[0].y(), 80, 1e-9) << "it rests as drawn under gravity";
    c.advance(1.0 / 60, kH, {0, -5}, 0, w);  // a jerk up, then still
    for (int f = 1; f <= 60 * 10; ++f) {
      c.advance(1.0 / 60, kH, {0, -5}, 0, w);
      t.push_back(f / 60.0);
      y.push_back(c.ends()[0].y() + 5);
    }
    const double got = 1 / mean_period(upward_crossings(t, y, 80));
    std::cout << "spring length " << got << " Hz (set 3 Hz)" << std::endl;
    EXPECT_NEAR(got, 3.0, 0.03 * 3.0);
  }
}

TEST(Chain, AmplitudeDecaysByTheDampingsFactorPerCycle) {
  for (double zeta : {0.05, 0.1, 0.2}) {
    ChainParams p;
    p.frequency = 1.5;
    p.damping = zeta;
    const Vec2 rest[] = {{0, 0}, {0, 100}};
    Chain c(rest, p);
    MotionWorld w;
    for (int f = 0; f < 4; ++f) c.advance(kH, kH, {0, 0}, 0, w);  // steps behind it: it feels the jerk
    c.advance(kH, kH, {3, 0}, 0, w);
    std::vector<double> x;
    for (int f = 0; f < 120 * 6; ++f) {  // a frame a step: each sample is a step's
      c.advance(kH, kH, {3, 0}, 0, w);
      x.push_back(c.simulated_end(0).x() - 3);
    }
    std::vector<double> peaks;
    for (size_t i = 1; i + 1 < x.size(); ++i)
      if (x[i] > x[i - 1] && x[i] >= x[i + 1] && x[i] > 1e-6) peaks.push_back(x[i]);
    ASSERT_GE(peaks.size(), 3u);
    const double want = std::exp(-2 * M_PI * zeta / std::sqrt(1 - zeta * zeta));
    const double got = peaks[2] / peaks[1];
    std::cout << "damping " << zeta << ": amplitude x" << got << " per cycle (theory " << want << ")" << std::endl;
    EXPECT_NEAR(got, want, 0.05 * want);
  }
}

// The parent sways and turns; the chain's ends at common times are the same whatever the
// frame rate (RMS difference <= 1% of the chain's length).
TEST(Chain, TheSameMotionAtThirtySixtyAndHundredFortyFourAndTwoFortyHz) {
  auto anchor = [](double t) { return Vec2(60 * std::sin(2 * M_PI * 0.7 * t), 20 * std::sin(2 * M_PI * 0.3 * t)); };
  auto rotation = [](double t) { return 0.3 * std::sin(2 * M_PI * 0.4 * t); };
  ChainParams p;
  p.frequency = 1.2;
  p.damping = 0.15;
  const Vec2 rest[] = {{0, 0}, {10, 40}, {15, 80}, {15, 120}};
  const double length = 40 * std::sqrt(1 + 1.0 / 16) + 40 * std::sqrt(1 + 1.0 / 64) + 40;
  MotionWorld w;
  w.gravity = {0, 300};
  std::vector<std::vector<Vec2>> at;  // per rate: the last end at t = k / 6 s
  for (int rate : {240, 144, 60, 30}) {
    Chain c(rest, p);
    c.reset(anchor(0), rotation(0));
    std::vector<Vec2> samples;
    const int per = rate / 6 * 1;  // frames per sixth of a second (30/6 = 5, 144/6 = 24)
    for (int f = 1; f <= rate * 6; ++f) {
      const double t = double(f) / rate;
      c.advance(1.0 / rate, kH, anchor(t), rotation(t), w);
      if (f % per == 0) samples.push_back(c.ends().back());
    }
    at.push_back(samples);
  }
  for (size_t r = 1; r < at.size(); ++r) {
    ASSERT_EQ(at[r].size(), at[0].size());
    double sum = 0;
    for (size_t k = 0; k < at[0].size(); ++k) sum += (at[r][k] - at[0][k]).squaredNorm();
    const double rms = std::sqrt(sum / double(at[0].size()));
    std::cout << "rate " << (r == 1 ? 144 : r == 2 ? 60 : 30) << " Hz vs 240 Hz: RMS " << 100 * rms / length << "% of the chain's length"
              << std::endl;
    EXPECT_LE(rms, 0.01 * length);
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

// 10^6 random parent jerks (and bad frames): every end finite, no link end faster than the
// limit, no allocation.
TEST(Chain, RandomJerksStayFiniteAndWithinTheLimit) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> jump(-400, 400), u(0, 1);
  for (ChainParams::Model model : {ChainParams::Pendulum, ChainParams::Spring}) {
    ChainParams p;
    p.model = model;
    p.frequency = 2;
    p.damping = 0.05;
    p.inertia = 2;
    p.limit = 900;
    const Vec2 rest[] = {{0, 0}, {0, 40}, {0, 80}, {0, 120}};
    Chain c(rest, p);
    MotionWorld w;
    w.gravity = {0, 980};
    Vec2 anchor(0, 0);
    std::vector<Vec2> before(c.links());
    double worst = 0;
    long bad = 0;
    const long allocs = test::allocation_count();
    for (long i = 0; i < 1000000; ++i) {
      anchor += Vec2(jump(rng), jump(rng)) * (u(rng) < 0.1 ? 1.0 : 0.01);
      if (anchor.norm() > 1e6) anchor = Vec2::Zero();
      const double rot = 3 * (u(rng) - 0.5);
      if (u(rng) < 1e-4) {  // bad frames: NaN, Inf, a negative step
        c.advance(std::nan(""), kH, anchor, rot, w);
        c.advance(kH, kH, Vec2(INFINITY, 0), rot, w);
        c.advance(-1, kH, anchor, NAN, w);
      }
      for (size_t k = 0; k < c.links(); ++k) before[k] = c.simulated_end(k);
      const long resets = c.resets();
      c.advance(kH, kH, anchor, rot, w);  // one step a frame: the speed is the step's change
      for (size_t k = 0; k < c.links(); ++k)
        if (!c.simulated_end(k).allFinite() || !c.ends()[k].allFinite()) ++bad;
      // The last link's end relative to the link before it: at most the limit, turning and
      // stretching together, per step (a reset puts it back at rest: not a speed).
      if (c.resets() == resets) {
        const Vec2 rel_now = c.simulated_end(c.links() - 1) - c.simulated_end(c.links() - 2);
        const Vec2 rel_before = before[c.links() - 1] - before[c.links() - 2];
        worst = std::max(worst, (rel_now - rel_before).norm() / kH);
      }
    }
    EXPECT_EQ(test::allocation_count() - allocs, 0) << "advance allocates nothing";
    EXPECT_EQ(bad, 0);
    std::cout << (model == ChainParams::Spring ? "spring" : "pendulum") << ": fastest link end " << worst << " units/s (limit " << p.limit
              << "), " << c.resets() << " resets, " << c.reverts() << " reverted steps" << std::endl;
    EXPECT_LE(worst, p.limit * 1.001);
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
