// Where a controller's lights go, and what it answers: a device's backend, or an in-process
// simulator (app/live_devices.cpp).
#pragma once

#include <cstdint>
#include <span>

namespace mar {

class LedSink {
 public:
  virtual ~LedSink() = default;
  /// Hands `message` to show device `device`; false when it could not be taken (counted).
  virtual bool send(uint16_t device, std::span<const uint8_t> message) = 0;
  /// Device `device`'s last whole SysEx and how many it has sent this connection (0: none).
  virtual std::span<const uint8_t> last_sysex(uint16_t device, uint64_t& count) {
    (void)device;
    count = 0;
    return {};
  }
};

}  // namespace mar
