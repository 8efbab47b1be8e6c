#include "input/midi_clock.h"

#include <algorithm>
#include <cmath>

namespace mar {

bool MidiClock::feed(uint8_t status, int64_t t_ns) {
  switch (status) {
    case 0xF8: tick(t_ns); return true;
    case 0xFA: start(); return false;
    case 0xFB: resume(); return false;
    case 0xFC: stop(); return false;
    default: return false;
  }
}

void MidiClock::start() {
  zero_ = seq_;
  paused_ = 0;
  running_ = true;
}

void MidiClock::resume() { running_ = true; }

void MidiClock::stop() {
  if (!running_) return;
  held_ = seq_ > 0 ? beats_at(t_[size_t((seq_ - 1) % kWindow)]) : 0;
  running_ = false;
}

void MidiClock::tick(int64_t t_ns) {
  if (n_ >= 2) {
    // Far off the line (over a third of a tick), or after a gap of 3 ticks: the tempo changed or
    // the clock jumped; the line starts afresh from the last tick.
    const double off = std::abs(double(t_ns) - time_of_seq(double(seq_)));
    const int64_t last = t_[size_t((seq_ - 1) % kWindow)];
    if (!(b_ns_ > 0) || off > b_ns_ / 3 || double(t_ns) - double(last) > 3 * b_ns_) n_ = 1;
  }
  t_[size_t(seq_ % kWindow)] = t_ns;
  ++seq_;
  n_ = std::min(n_ + 1, kWindow);
  if (!running_) ++paused_;  // (ticks while stopped are not song time)
  fit();
}

void MidiClock::fit() {
  origin_ = t_[size_t((seq_ - n_) % kWindow)];
  if (n_ < 2) {
    a_ns_ = 0;
    b_ns_ = 0;
    return;
  }
  // Least squares of t = a + b x, x = 0..n-1, times relative to the oldest tick.
  const double n = n_;
  const double sx = n * (n - 1) / 2, sxx = (n - 1) * n * (2 * n - 1) / 6;
  double st = 0, sxt = 0;
  for (int i = 0; i < n_; ++i) {
    // In double: a recording's times can be any 64-bit value, and their difference overflow.
    const double t = double(t_[size_t((seq_ - n_ + i) % kWindow)]) - double(origin_);
    st += t;
    sxt += i * t;
  }
  b_ns_ = (n * sxt - sx * st) / (n * sxx - sx * sx);
  a_ns_ = (st - b_ns_ * sx) / n;
}

double MidiClock::bpm() const { return locked() && b_ns_ > 0 ? 60e9 / (b_ns_ * kPerBeat) : 0; }

double MidiClock::beats_at(int64_t t_ns) const {
  if (!running_) return held_;
  if (!locked() || !(b_ns_ > 0)) return 0;
  const double s = double(seq_ - n_) + (double(t_ns) - double(origin_) - a_ns_) / b_ns_;  // arrival count at t
  return (s - double(zero_ + paused_)) / kPerBeat;
}

double MidiClock::beat_phase(int64_t t_ns) const {
  const double b = beats_at(t_ns);
  return b - std::floor(b);
}

double MidiClock::bar_phase(int64_t t_ns, int beats_per_bar) const {
  const double b = beats_at(t_ns) / double(beats_per_bar > 0 ? beats_per_bar : 4);
  return b - std::floor(b);
}

}  // namespace mar
