#include "app/loop/service.h"

#include <systemd/sd-daemon.h>

#include <chrono>
#include <cstdlib>

namespace mar {

ServiceNotifier::ServiceNotifier() {
  const char* socket = std::getenv("NOTIFY_SOCKET");
  if (!socket || !*socket) return;
  uint64_t usec = 0;
  if (sd_watchdog_enabled(0, &usec) > 0) watchdog_usec_ = usec;
  thread_ = std::thread([this] { loop(); });
}

ServiceNotifier::~ServiceNotifier() {
  if (!thread_.joinable()) return;
  {
    std::lock_guard lock(m_);
    stop_ = true;
  }
  cv_.notify_all();
  thread_.join();
  sd_notify(0, "STOPPING=1");
}

void ServiceNotifier::reloading() {
  if (!thread_.joinable()) return;
  sd_notify(0, "RELOADING=1");
  rearm_.store(true);
}

void ServiceNotifier::loop() {
  // Until the first frame: look every 20 ms. Then ping at half the watchdog interval when the
  // frame count moved since the last look.
  bool ready = false;
  uint64_t seen = 0;
  std::unique_lock lock(m_);
  while (!stop_) {
    const auto wait = ready && watchdog_usec_ > 0 ? std::chrono::microseconds(watchdog_usec_ / 2)
                                                 : std::chrono::microseconds(ready ? 1'000'000 : 20'000);
    cv_.wait_for(lock, wait, [&] { return stop_; });
    if (rearm_.exchange(false)) ready = false, frames_.store(0);
    const uint64_t now = frames_.load(std::memory_order_relaxed);
    if (stop_) {
      if (!ready && now > 0) sd_notify(0, "READY=1");  // a show shorter than one look
      break;
    }
    if (!ready) {
      if (now == 0) continue;
      sd_notify(0, "READY=1\nSTATUS=presenting frames");
      ready = true;
      seen = now;
      continue;
    }
    if (watchdog_usec_ > 0 && now != seen) sd_notify(0, "WATCHDOG=1");
    seen = now;
  }
}

}  // namespace mar
