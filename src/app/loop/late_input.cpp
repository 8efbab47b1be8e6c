#include "app/loop/late_input.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace mar {

void LateInput::configure(bool timed, bool on, double period_us, double margin_us) {
  timed_ = timed;
  on_ = timed && on;
  period_us_ = period_us;
  base_margin_us_ = margin_us_ = std::clamp(margin_us, 0.0, period_us / 2);
}

void LateInput::set_display(bool vsync, int refresh_hz) {
  vsync_ = vsync;
  refresh_hz_ = refresh_hz;
}

double LateInput::lead_us() const {
  if (!on_) return 0;
  if (n_ == 0) return period_us_;
  double predicted = 0;
  for (size_t i = 0; i < n_; ++i) predicted = std::max(predicted, recent_[i]);
  return std::min(predicted + margin_us_, period_us_);
}

void LateInput::frame(int64_t deadline, int64_t read, int64_t ready, int64_t presented, int64_t newest, bool counted) {
  const int64_t done = vsync_ ? ready : presented;  // (with vsync, present waits for the flip)
  const double compute_us = double(done - read) * 1e-3;
  const double lead = lead_us();
  recent_[at_] = compute_us;
  at_ = (at_ + 1) % recent_.size();
  n_ = std::min(n_ + 1, recent_.size());
  const bool missed = done > deadline;
  if (!counted) return;
  if (vsync_ && last_presented_ >= 0) present_interval_.add(double(presented - last_presented_) * 1e-3);
  last_presented_ = presented;  // warm-up: the prediction learns, the margin and the figures wait
  if (on_ && missed) {  // more careful: the margin grows by what it missed by, for a while
    margin_us_ = std::min(margin_us_ + double(done - deadline) * 1e-3, period_us_ / 2);
    since_miss_ = 0;
  } else if (++since_miss_ >= 120) {
    margin_us_ = std::max(base_margin_us_, base_margin_us_ + 0.8 * (margin_us_ - base_margin_us_));
    since_miss_ = 0;
  }
  ++frames_;
  if (on_ && missed) ++misses_;
  lead_.add(lead);
  read_to_ready_.add(double(ready - read) * 1e-3);
  ready_to_present_.add(double(presented - ready) * 1e-3);
  if (newest < 0) return;
  // The tick that shows this frame: its deadline, or the first one after it was presented.
  const double period_ns = period_us_ * 1e3;
  const double late = double(presented - deadline);
  const double tick = double(deadline) + (late > 0 ? std::ceil(late / period_ns) * period_ns : 0);
  device_to_read_.add(double(read - newest) * 1e-3);
  newest_to_ready_.add(double(ready - newest) * 1e-3);
  newest_to_tick_.add((tick - double(newest)) * 1e-3);
  if (vsync_) newest_to_present_.add(double(presented - newest) * 1e-3);
}

void LateInput::add_stats(nlohmann::json& stats) const {
  using json = nlohmann::json;
  auto h = [](const Histogram& x) {
    return json{{"p50", x.quantile(0.5)}, {"p99", x.quantile(0.99)}, {"max", x.max()}, {"frames", x.count()}};
  };
  stats["late_input"] = {
      {"on", on_},
      {"frames", frames_},
      {"missed_deadlines", misses_},
      {"margin_us", margin_us_},
      {"lead_us", h(lead_)},
      {"device_to_read_us", h(device_to_read_)},
      {"read_to_ready_us", h(read_to_ready_)},
      {"ready_to_present_us", h(ready_to_present_)},
      {"newest_input_to_ready_us", h(newest_to_ready_)},
      {"newest_input_to_shown_us", h(newest_to_tick_)},
  };
  // The refresh: the display's, or what vsync held the presents to.
  const bool measured = refresh_hz_ <= 0 && present_interval_.count() >= 10 && present_interval_.quantile(0.1) > 0;
  const double hz = refresh_hz_ > 0 ? refresh_hz_ : measured ? 1e6 / present_interval_.quantile(0.1) : 0;
  stats["late_input"]["display"] = {{"vsync", vsync_}, {"refresh_hz", hz},
                                    {"refresh_from", refresh_hz_ > 0 ? "display" : measured ? "present intervals" : "none"}};
  json& photon = stats["late_input"]["newest_input_to_photon_us_estimate"];
  if (!vsync_) {
    photon = "not estimated: no vsync ([display] vsync = true)";
  } else if (hz <= 0 || newest_to_present_.count() == 0) {
    photon = "not estimated: the refresh rate is not known yet";
  } else {
    const double half = 0.5e6 / hz;  // the scanout to the middle of the screen
    photon = {{"p50", newest_to_present_.quantile(0.5) + half}, {"p99", newest_to_present_.quantile(0.99) + half},
              {"max", newest_to_present_.max() + half}, {"frames", newest_to_present_.count()}};
  }
}

}  // namespace mar
