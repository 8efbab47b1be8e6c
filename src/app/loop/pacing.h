// The show clock and frame pacing. Headless shows run on a virtual clock: frame k is at
// k x period, as fast as the machine goes. Windowed shows and shows with hardware follow
// CLOCK_MONOTONIC from the show's epoch (the clock device timestamps use), and wait for
// each frame's wake-up (its deadline less the late-input lead, loop/late_input.h) after the
// frame's work, never inside it.
#pragma once

#include <cstdint>

namespace mar {

class Pacer {
 public:
  Pacer(double period_s, bool realtime) : period_s_(period_s), realtime_(realtime) {}
  /// Show time 0 on CLOCK_MONOTONIC (ns); the pacing deadlines start at the first wait().
  void set_epoch(int64_t mono_ns) { epoch_ns_ = mono_ns; }
  int64_t epoch() const { return epoch_ns_; }
  /// Pacing starts now: frame k is due k periods from here.
  void start();
  /// Show time of frame `k` (ns).
  int64_t time_of(long k) const;
  /// Realtime: sleeps until `lead_us` before frame `k` is due (k periods after start());
  /// headless: returns.
  void wait_for(long k, double lead_us = 0);
  /// When frame `k` is due, on CLOCK_MONOTONIC (ns; realtime, after start()).
  int64_t deadline(long k) const { return start_ns_ + int64_t(double(k) * period_s_ * 1e9); }
  double period_s() const { return period_s_; }
  bool realtime() const { return realtime_; }

 private:
  double period_s_;
  bool realtime_;
  int64_t epoch_ns_ = 0, start_ns_ = -1;
};

}  // namespace mar
