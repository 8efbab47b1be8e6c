#include "motion/behavior.h"

#include "motion/chain.h"

#include <algorithm>
#include <cmath>

namespace mar {

namespace {

// splitmix64: a small, well-mixed generator; the same seed, the same sequence everywhere.
uint64_t next(uint64_t& x) {
  uint64_t z = (x += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

double uniform(uint64_t& x) { return double(next(x) >> 11) * (1.0 / 9007199254740992.0); }

}  // namespace

Behavior::Behavior(const BehaviorSpec& s) : s_(s), rng_(s.seed) {
  s_.mean = std::max(0.05, s_.mean);
  s_.jitter = std::clamp(s_.jitter, 0.0, 0.95);
  s_.hold = std::clamp(s_.hold, 0.01, s_.mean);
  s_.period = std::max(0.05, s_.period);
  until_ = s_.sync_beat ? std::ceil(next_interval()) : next_interval();
}

double Behavior::next_interval() { return s_.mean * (1 + s_.jitter * (2 * uniform(rng_) - 1)); }

void Behavior::step(double dt, bool touched, double beats) {
  if (!(dt >= 0) || !std::isfinite(dt)) dt = 0;
  t_ += dt;
  tau_ = s_.sync_beat && std::isfinite(beats) ? beats : t_;
  // A performer's control on the target: paused at once, back `resume` s after the last write.
  since_touch_ = touched ? 0.0 : since_touch_ + dt;
  const double back = since_touch_ - s_.resume;
  weight_ = back <= 0 ? 0.0 : s_.fade > 0 ? std::min(1.0, back / s_.fade) : 1.0;
  if (s_.kind != BehaviorSpec::Blink) return;
  if (s_.sync_beat) {  // on the beat: starts when the music time reaches a whole beat
    if (on_) {
      if (t_ >= shut_until_) on_ = false;
    } else if (tau_ >= until_) {
      if (weight_ >= 1) {
        on_ = true;
        ++blinks_;
        shut_until_ = t_ + s_.hold;
      }
      until_ = std::ceil(tau_ + std::max(1.0, next_interval()) - 1e-9);
    }
    return;
  }
  if (on_) {
    if (t_ >= until_) {
      on_ = false;
      until_ = t_ + std::max(0.0, next_interval() - s_.hold);
    }
  } else if (t_ >= until_) {
    if (weight_ >= 1) {  // (not while paused: the interval starts again)
      on_ = true;
      ++blinks_;
      until_ = t_ + s_.hold;
    } else {
      until_ = t_ + next_interval();
    }
  }
}

Vec2 Behavior::offset() const {
  switch (s_.kind) {
    case BehaviorSpec::Breathe: return weight_ * 0.5 * (1 - std::cos(2 * M_PI * tau_ / s_.period)) * s_.depth;
    case BehaviorSpec::Look: {
      const double u = 2 * M_PI * s_.speed * tau_, sd = double(s_.seed % 1000);
      return weight_ * Vec2(s_.range.x() * smooth_noise(u, sd), s_.range.y() * smooth_noise(u, sd + 0.5));
    }
    case BehaviorSpec::Blink: break;
  }
  return Vec2::Zero();
}

double Behavior::value() const {
  switch (s_.kind) {
    case BehaviorSpec::Breathe: return weight_ * 0.5 * (1 - std::cos(2 * M_PI * tau_ / s_.period)) * s_.amount;
    case BehaviorSpec::Look: return weight_ * s_.amount * smooth_noise(2 * M_PI * s_.speed * tau_, double(s_.seed % 1000));
    case BehaviorSpec::Blink: break;
  }
  return 0;
}

}  // namespace mar
