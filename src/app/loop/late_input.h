// Late input: on the wall clock a frame reads its inputs as late as its compute allows. Frame k
// is due at its deadline (the pacer's tick: when a display or a stream that samples at the
// show's rate takes it); it wakes at the deadline minus the predicted compute minus a margin,
// then reads, computes and presents, so what it shows is as fresh as the frame's own cost
// permits (docs/algorithms.md §8, "late input").
//
// The prediction is the largest compute time of the last 64 frames; the margin starts at
// `margin_us`, grows by what a frame missed its deadline by (up to half a period), and gives back
// a fifth of what it grew every 120 frames without a miss. On the virtual clock nothing of this is
// used: a frame reads what happened by its show time, so a busy machine changes nothing.
//
// It also keeps the run's latency split (`--stats` "late_input"): device -> read (the newest
// input's age when the frame read), read -> frame ready (the frame's work up to its picture),
// frame ready -> present returned, and the newest input's age at the tick that shows the frame
// (the first deadline at or after present returned). Adding never allocates.
//
// In a window with vsync ([display] vsync) present returns at the display's flip, so a frame's
// cost is read -> frame ready (present's wait for the refresh is not work) and a miss is a frame
// not ready by its deadline; and the newest input's age is estimated to the photon: its age when
// present returned plus half a refresh, the scanout's way to the middle of the screen (a
// compositor may add a refresh more: not counted, so an estimate from below). The refresh is the
// display's as SDL gives it, or, where it gives none (Xvfb), measured: the 10th percentile of
// the intervals between present returns, which vsync holds to the refresh.
#pragma once

#include "app/stats.h"

#include <nlohmann/json_fwd.hpp>

#include <array>
#include <cstdint>

namespace mar {

class LateInput {
 public:
  /// `timed`: frames have deadlines (the wall clock; not a replay). `on`: late input (false: a
  /// frame reads at its deadline, as before). `period_us`: the frame period; `margin_us`: the
  /// starting margin.
  void configure(bool timed, bool on, double period_us, double margin_us);
  bool timed() const { return timed_; }
  /// The window: present waits for the refresh (`vsync`), at `refresh_hz` (0: not known; then
  /// it is measured from the presents).
  void set_display(bool vsync, int refresh_hz);
  bool on() const { return on_; }
  /// How long before its deadline the next frame wakes (us): the whole period until a frame
  /// was measured (it reads right after the last one), 0 when late input is off.
  double lead_us() const;
  /// One frame, on one clock (ns): `deadline` it was due, `read` it read its inputs, `ready` its
  /// picture was drawn, `presented` present returned, `newest` its newest input (-1: none).
  /// `counted`: after warm-up (the statistics; the prediction learns from every frame).
  void frame(int64_t deadline, int64_t read, int64_t ready, int64_t presented, int64_t newest, bool counted);
  long misses() const { return misses_; }
  double margin_us() const { return margin_us_; }
  /// Adds "late_input" to the stats object.
  void add_stats(nlohmann::json& stats) const;

 private:
  bool timed_ = false, on_ = false, vsync_ = false;
  int refresh_hz_ = 0;
  double period_us_ = 0, base_margin_us_ = 500, margin_us_ = 500;
  std::array<double, 64> recent_{};  ///< the last frames' compute (read -> present returned), us
  size_t n_ = 0, at_ = 0;
  long since_miss_ = 0, misses_ = 0, frames_ = 0;
  Histogram lead_, device_to_read_, read_to_ready_, ready_to_present_, newest_to_ready_, newest_to_tick_;
  Histogram newest_to_present_, present_interval_;  ///< with vsync: the photon estimate's parts
  int64_t last_presented_ = -1;
};

}  // namespace mar
