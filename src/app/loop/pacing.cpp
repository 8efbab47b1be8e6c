#include "app/loop/pacing.h"

#include "devices/device.h"

#include <cmath>
#include <ctime>

namespace mar {

int64_t Pacer::time_of(long k) const {
  if (realtime_) return monotonic_ns() - epoch_ns_;
  return int64_t(std::llround(double(k) * period_s_ * 1e9));
}

void Pacer::start() { start_ns_ = monotonic_ns(); }

void Pacer::wait_for(long k, double lead_us) {
  if (!realtime_) return;
  const int64_t now = monotonic_ns();
  if (start_ns_ < 0) start_ns_ = now;
  const int64_t due = deadline(k) - int64_t(lead_us * 1e3);
  if (due <= now) return;
  timespec ts{time_t(due / 1000000000), long(due % 1000000000)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) != 0) {
  }
}

}  // namespace mar
