// The secondary-motion figures (docs/algorithms.md §8), measured the same way by the tests
// (tests/motion/test_chain.cpp: asserted) and the benchmark (tests/bench/bench_motion.cpp:
// printed for README).
#pragma once

#include "motion/chain.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace mar::measure {

constexpr double kStep = 1.0 / 120;  // the default fixed step

/// Times where `x` crosses `mean` going up, interpolated.
inline std::vector<double> upward_crossings(const std::vector<double>& t, const std::vector<double>& x, double mean) {
  std::vector<double> out;
  for (size_t i = 1; i < x.size(); ++i)
    if (x[i - 1] < mean && x[i] >= mean) out.push_back(t[i - 1] + (mean - x[i - 1]) / (x[i] - x[i - 1]) * (t[i] - t[i - 1]));
  return out;
}

inline double mean_period(const std::vector<double>& c) { return c.size() < 2 ? 0 : (c.back() - c.front()) / double(c.size() - 1); }

/// A rigid pendulum of length L under gravity g, drawn 4 degrees off the vertical, undamped,
/// run with 60 Hz frames for 20 s: its period (theory 2 pi sqrt(L / g)).
inline double pendulum_period(double L, double g) {
  ChainParams p;
  p.damping = 0;
  const double a0 = 4 * M_PI / 180;
  const Vec2 rest[] = {{0, 0}, {L * std::sin(a0), L * std::cos(a0)}};
  Chain c(rest, p);
  MotionWorld w;
  w.gravity = {0, g};
  std::vector<double> t, x;
  for (int f = 1; f <= 60 * 20; ++f) {
    c.advance(1.0 / 60, kStep, {0, 0}, 0, w);
    t.push_back(f / 60.0);
    x.push_back(c.ends()[0].x());
  }
  return mean_period(upward_crossings(t, x, 0));
}

/// The angular spring's frequency (no gravity), set to `hz`, after a sideways jerk.
inline double spring_frequency(double hz) {
  ChainParams p;
  p.frequency = hz;
  p.damping = 0;
  const Vec2 rest[] = {{0, 0}, {0, 80}};
  Chain c(rest, p);
  MotionWorld w;
  std::vector<double> t, x;
  for (int f = 0; f < 4; ++f) c.advance(1.0 / 60, kStep, {0, 0}, 0, w);
  c.advance(1.0 / 60, kStep, {6, 0}, 0, w);
  for (int f = 1; f <= 60 * 10; ++f) {
    c.advance(1.0 / 60, kStep, {6, 0}, 0, w);
    t.push_back(f / 60.0);
    x.push_back(c.ends()[0].x() - 6);
  }
  return 1 / mean_period(upward_crossings(t, x, 0));
}

/// The spring model's length frequency, set to `hz`, under gravity, after a jerk along it.
inline double spring_length_frequency(double hz) {
  ChainParams p;
  p.model = ChainParams::Spring;
  p.frequency = hz;
  p.damping = 0;
  const Vec2 rest[] = {{0, 0}, {0, 80}};
  Chain c(rest, p);
  MotionWorld w;
  w.gravity = {0, 400};
  std::vector<double> t, y;
  for (int f = 0; f < 4; ++f) c.advance(1.0 / 60, kStep, {0, 0}, 0, w);
  c.advance(1.0 / 60, kStep, {0, -5}, 0, w);
  for (int f = 1; f <= 60 * 10; ++f) {
    c.advance(1.0 / 60, kStep, {0, -5}, 0, w);
    t.push_back(f / 60.0);
    y.push_back(c.ends()[0].y() + 5);
  }
  return 1 / mean_period(upward_crossings(t, y, 80));
}

/// The amplitude's ratio from one cycle to the next with damping ratio zeta (theory
/// exp(-2 pi zeta / sqrt(1 - zeta^2))), a step a frame.
inline double decay_per_cycle(double zeta) {
  ChainParams p;
  p.frequency = 1.5;
  p.damping = zeta;
  const Vec2 rest[] = {{0, 0}, {0, 100}};
  Chain c(rest, p);
  MotionWorld w;
  for (int f = 0; f < 4; ++f) c.advance(kStep, kStep, {0, 0}, 0, w);
  c.advance(kStep, kStep, {3, 0}, 0, w);
  std::vector<double> x;
  for (int f = 0; f < 120 * 6; ++f) {
    c.advance(kStep, kStep, {3, 0}, 0, w);
    x.push_back(c.simulated_end(0).x() - 3);
  }
  std::vector<double> peaks;
  for (size_t i = 1; i + 1 < x.size(); ++i)
    if (x[i] > x[i - 1] && x[i] >= x[i + 1] && x[i] > 1e-6) peaks.push_back(x[i]);
  return peaks.size() >= 3 ? peaks[2] / peaks[1] : 0;
}

/// A 3-link chain under a swaying, turning parent at `rate` Hz frames against 240 Hz frames:
/// the RMS difference of its end at common times (every 1/6 s for 6 s), % of its length.
inline double frame_rate_rms_pct(int rate) {
  auto anchor = [](double t) { return Vec2(60 * std::sin(2 * M_PI * 0.7 * t), 20 * std::sin(2 * M_PI * 0.3 * t)); };
  auto rotation = [](double t) { return 0.3 * std::sin(2 * M_PI * 0.4 * t); };
  ChainParams p;
  p.frequency = 1.2;
  p.damping = 0.15;
  const Vec2 rest[] = {{0, 0}, {10, 40}, {15, 80}, {15, 120}};
  const double length = 40 * std::sqrt(1 + 1.0 / 16) + 40 * std::sqrt(1 + 1.0 / 64) + 40;
  MotionWorld w;
  w.gravity = {0, 300};
  auto run = [&](int r) {
    Chain c(rest, p);
    c.reset(anchor(0), rotation(0));
    std::vector<Vec2> samples;
    for (int f = 1; f <= r * 6; ++f) {
      const double t = double(f) / r;
      c.advance(1.0 / r, kStep, anchor(t), rotation(t), w);
      if (f % (r / 6) == 0) samples.push_back(c.ends().back());
    }
    return samples;
  };
  const std::vector<Vec2> ref = run(240), got = run(rate);
  double sum = 0;
  for (size_t k = 0; k < ref.size() && k < got.size(); ++k) sum += (got[k] - ref[k]).squaredNorm();
  return 100 * std::sqrt(sum / double(std::max<size_t>(1, ref.size()))) / length;
}

struct Jerks {
  long bad = 0;       ///< non-finite ends
  double fastest = 0; ///< the last link's end relative to the link before, units/s
  long resets = 0, reverts = 0;
  long allocations = 0; ///< in advance(), with an allocation counter given
};
/// `n` random parent jerks (a step a frame; now and then a NaN, an Inf, a negative step) on a
/// 3-link chain with `limit` 900 units/s.
inline Jerks random_jerks(ChainParams::Model model, long n, long (*count_allocations)() = nullptr, unsigned seed = 7) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> jump(-400, 400), u(0, 1);
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
  Jerks out;
  const long allocs = count_allocations ? count_allocations() : 0;
  for (long i = 0; i < n; ++i) {
    anchor += Vec2(jump(rng), jump(rng)) * (u(rng) < 0.1 ? 1.0 : 0.01);
    if (anchor.norm() > 1e6) anchor = Vec2::Zero();
    const double rot = 3 * (u(rng) - 0.5);
    if (u(rng) < 1e-4) {
      c.advance(std::nan(""), kStep, anchor, rot, w);
      c.advance(kStep, kStep, Vec2(INFINITY, 0), rot, w);
      c.advance(-1, kStep, anchor, NAN, w);
    }
    const Vec2 before = c.simulated_end(2) - c.simulated_end(1);
    const long resets = c.resets();
    c.advance(kStep, kStep, anchor, rot, w);
    for (size_t k = 0; k < c.links(); ++k)
      if (!c.simulated_end(k).allFinite() || !c.ends()[k].allFinite()) ++out.bad;
    if (c.resets() == resets) out.fastest = std::max(out.fastest, ((c.simulated_end(2) - c.simulated_end(1)) - before).norm() / kStep);
  }
  if (count_allocations) out.allocations = count_allocations() - allocs;
  out.resets = c.resets();
  out.reverts = c.reverts();
  return out;
}

}  // namespace mar::measure
