// `[osc_out]`: the show's state sent as OSC over UDP (liblo) for lighting desks, TouchOSC
// layouts or another marionette to follow. A value is sent when it changes, at most `rate` times
// a second, from a thread of its own; the frame thread only writes the newest ShowState into a
// triple buffer (no allocation, no lock, no system call). Address space (PREFIX: "/marionette"):
//   PREFIX/handle/NAME      f f   where the handle is on the deformed character (x, y)
//   PREFIX/key/NAME         f     a key pose's weight
//   PREFIX/swap/SET         s     the member that shows
//   PREFIX/trigger/NAME     i     1 while on
//   PREFIX/device/NAME      s     connected | waiting | unplugged | denied | unavailable
//   PREFIX/frame            f f   the frame's compute and its input latency, ms
// Changes of one tick go in one bundle (or several, each under 1,200 bytes). A failed send is
// said once and counted; the show goes on.
#pragma once

#include "output/show_state.h"

#include <atomic>
#include <memory>
#include <string>
#include <thread>

namespace mar {

struct OscOutOptions {
  std::string host = "127.0.0.1";  ///< loopback unless told otherwise
  int port = 9000;
  double rate = 30;                ///< sends a second, at most
  std::string prefix = "/marionette";
};

class OscOut {
 public:
  /// Resolves `host` and starts the sender. Errors name the host and port.
  static std::unique_ptr<OscOut> open(const OscOutOptions& o, const ShowStateLayout& layout, std::string* error);
  /// Sends what was last published and stops the sender (the destructor does it too).
  void stop();
  ~OscOut();
  OscOut(const OscOut&) = delete;
  OscOut& operator=(const OscOut&) = delete;

  /// The frame thread: a slot to fill (sized for the layout), then publish() it.
  ShowState& state() { return slots_[back_]; }
  void publish();

  uint64_t messages() const { return messages_.load(); }
  uint64_t bundles() const { return bundles_.load(); }
  uint64_t send_errors() const { return errors_.load(); }
  const OscOutOptions& options() const { return o_; }

  struct Link;

 private:
  OscOut() = default;
  void run();
  OscOutOptions o_;
  ShowStateLayout layout_;
  ShowState slots_[3];
  int back_ = 0;                 ///< the frame thread's
  std::atomic<int> mid_{1};      ///< the slot between; bit 4: fresh
  int front_ = 2;                ///< the sender's
  std::unique_ptr<Link> link_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<uint64_t> messages_{0}, bundles_{0}, errors_{0};
};

}  // namespace mar
