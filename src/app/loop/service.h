// systemd's notify protocol for a show run as a service (config/systemd/): READY=1 once the
// first frame has been presented, then WATCHDOG=1 every half watchdog interval — but only while
// frames keep coming. A thread of its own does the talking; the frame only bumps a counter
// (one relaxed atomic add: no system call, no lock, no allocation), so a stalled frame loop
// stops the pings and systemd restarts the show (WatchdogSec). Outside systemd
// (no NOTIFY_SOCKET) it does nothing.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>

namespace mar {

class ServiceNotifier {
 public:
  /// Reads NOTIFY_SOCKET and WATCHDOG_USEC (libsystemd: sd_watchdog_enabled) and starts the
  /// thread when a service manager listens.
  ServiceNotifier();
  /// Sends STOPPING=1 and joins the thread.
  ~ServiceNotifier();
  ServiceNotifier(const ServiceNotifier&) = delete;
  ServiceNotifier& operator=(const ServiceNotifier&) = delete;

  /// The frame thread: a frame was presented.
  void frame_presented() { frames_.fetch_add(1, std::memory_order_relaxed); }
  /// The show file is being read again: RELOADING=1 now, READY=1 after the next frame.
  void reloading();
  bool active() const { return thread_.joinable(); }
  /// The watchdog interval (µs), 0 when systemd set none.
  uint64_t watchdog_usec() const { return watchdog_usec_; }

 private:
  void loop();
  std::atomic<uint64_t> frames_{0};
  std::atomic<bool> rearm_{false};
  uint64_t watchdog_usec_ = 0;
  std::mutex m_;
  std::condition_variable cv_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace mar
