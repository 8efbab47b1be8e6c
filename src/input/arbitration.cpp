#include "input/arbitration.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mar {

namespace {
constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
}

void Arbiter::set_sources(std::vector<SourcePriority> sources) {
  spec_ = std::move(sources);
  reset();
}

void Arbiter::reset() {
  own_.assign(spec_.size(), kNone);
  moved_.assign(spec_.size(), -std::numeric_limits<double>::infinity());
  holder_ = -1;
  value_ = kNone;
  easing_ = false;
}

bool Arbiter::active(int s, double now) const {
  return std::isfinite(own_[size_t(s)]) && now - moved_[size_t(s)] <= spec_[size_t(s)].hold;
}

void Arbiter::take(int s) {
  // From where the target is now to the new holder's value, over its hand-over time.
  holder_ = s;
  from_ = value_;
  t_ = 0;
  seconds_ = spec_[size_t(s)].handover;
  easing_ = std::isfinite(from_) && seconds_ > 0;
  value_ = easing_ ? from_ : own_[size_t(s)];
}

double Arbiter::follow() const {
  const double to = own_[size_t(holder_)];
  if (!easing_) return to;
  const double u = std::min(1.0, t_ / seconds_);
  const double e = u < 0.5 ? 2 * u * u : 1 - 2 * (1 - u) * (1 - u);  // in-out, as poses ease
  return from_ + e * (to - from_);
}

void Arbiter::write(int s, double v, double now) {
  if (!std::isfinite(v)) return;
  own_[size_t(s)] = v;
  moved_[size_t(s)] = now;
  if (holder_ < 0) {  // the first: nothing to hand over from
    holder_ = s;
    value_ = v;
    return;
  }
  if (s != holder_ && (spec_[size_t(s)].priority >= spec_[size_t(holder_)].priority || !active(holder_, now))) take(s);
  value_ = follow();
}

double Arbiter::update(double now, double dt) {
  if (holder_ < 0) return value_;
  if (!active(holder_, now)) {
    // Let go: the highest-priority source still moving (the latest of equals), else the
    // lowest-priority source with a value below the holder (the base it overrode).
    int next = -1;
    for (size_t k = 0; k < spec_.size(); ++k) {
      if (int(k) == holder_ || !active(int(k), now)) continue;
      if (next < 0 || spec_[k].priority > spec_[size_t(next)].priority ||
          (spec_[k].priority == spec_[size_t(next)].priority && moved_[k] > moved_[size_t(next)]))
        next = int(k);
    }
    if (next < 0)
      for (size_t k = 0; k < spec_.size(); ++k) {
        if (int(k) == holder_ || !std::isfinite(own_[k]) || spec_[k].priority >= spec_[size_t(holder_)].priority) continue;
        if (next < 0 || spec_[k].priority < spec_[size_t(next)].priority ||
            (spec_[k].priority == spec_[size_t(next)].priority && moved_[k] > moved_[size_t(next)]))
          next = int(k);
      }
    if (next >= 0) take(next);
  }
  if (easing_) {
    t_ += std::max(0.0, dt);
    value_ = follow();
    if (t_ >= seconds_) easing_ = false;
  } else {
    value_ = own_[size_t(holder_)];
  }
  return value_;
}

}  // namespace mar
