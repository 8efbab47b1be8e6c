// LED feedback from state: a controller's lights show what the show is doing, not what was
// pressed. From the profile's [leds] (config/devices/*.toml), each binding whose control has a
// light drives it from the state its target holds:
//   - a trigger (toggled, latched or held) lights while it is on; a swap member while it shows;
//   - a [[pose]] button while its pose is the current one (the last pressed, until another control
//     moves a handle it placed);
//   - an encoder's ring (X-Touch Mini) shows the bound value from the low end of its range.
// Lit is the binding's `led` colour (a name of the device's palette: the APC mini mk2's pads, the
// Launch Control XL's buttons) or the profile's `on`; dark is its `off`.
// A light is sent when what it should show changes, at most once per 20 ms (a change within
// that is sent when it ends: the last one wins) and at most 32 messages a frame (the rest the
// next frame), so a controller's input is never flooded. The frame only hands the message to
// the device's backend, whose own thread writes it (USB-MIDI: a lock-free ring to its I/O
// thread); an in-process simulator takes it at once. A device that connects (or reconnects)
// gets its profile's init messages (and a nanoKONTROL2 its External LED mode: app/loop/
// korg_setup.h), then every light again. A controller that echoes what it
// is sent (MIDI thru) would press its own buttons: an incoming note or CC equal to a light's
// message sent within the last 100 ms is dropped and counted. Allocation-free after prepare().
#pragma once

#include "app/loop/korg_setup.h"
#include "app/loop/led_sink.h"
#include "app/show.h"
#include "devices/device.h"
#include "input/event.h"
#include "input/mapping.h"

#include <nlohmann/json_fwd.hpp>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace mar {

class LedFeedback {
 public:
  static constexpr int64_t kMinInterval = 20'000'000, kEchoWindow = 100'000'000;
  static constexpr int kPerFrame = 32;
  /// The lights `show`'s bindings drive (allocates).
  void prepare(const ShowConfig& show, const Mapping& m);
  bool empty() const { return lights_.empty() && inits_.empty(); }
  /// One frame at show time `t_ns`: what each light shows from the state; changes go to `out`.
  /// `swap_members`, `triggers`: what shows now; `states`: each device's connection.
  void frame(int64_t t_ns, const Mapping& m, std::span<const int> swap_members, std::span<const char> triggers,
             std::span<const DeviceState> states, LedSink& out);
  /// Whether event `e` is the echo of a light sent within the echo window (then it is dropped).
  bool echo(const Event& e, int64_t t_ns);
  /// How a device's setup ended, once: true with its show device and a sentence.
  bool take_news(uint16_t& device, const char*& text);
  /// Adds "leds" (lights, sent, deferred, failed, echoes, inits) to the --stats object.
  void add_stats(nlohmann::json& stats) const;
  uint64_t sent() const { return sent_; }
  uint64_t echoes() const { return echoes_; }

 private:
  enum class Source : uint8_t { Trigger, Swap, Pose, Ring };
  struct Light {
    uint16_t device = 0;
    Source source = Source::Trigger;
    int index = 0, member = 0, binding = 0;
    std::array<uint8_t, 64> bytes{};
    uint8_t size = 0, value_at = 0;
    int on = 127, off = 0, lo = 0, hi = 127;
    int want = -1, sent = -1;  ///< -1: not yet
    int64_t sent_at = INT64_MIN / 2;
  };
  struct Init {
    uint16_t device = 0;
    std::vector<std::vector<uint8_t>> messages;
    bool korg = false;  ///< then its LED mode is set (korg_setup.h) after its messages
    KorgLedSetup setup;
    bool sent = false, done = false;
  };
  std::vector<char> waiting_;  ///< per show device: its lights wait for its setup
  std::vector<Light> lights_;
  std::vector<Init> inits_;
  uint64_t sent_ = 0, deferred_ = 0, failed_ = 0, echoes_ = 0, init_sent_ = 0;
};

}  // namespace mar
