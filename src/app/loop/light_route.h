// Where a show's lights go and where a controller's answers come from (a LedSink): an
// in-process simulator takes a light at once; any other device through the device set, whose
// backend's thread writes it (USB-MIDI hands it to its I/O thread through a lock-free ring).
// It holds the show's own simulators and device set by reference (a reload's swap changes what
// they hold, not where they are). No allocation.
#pragma once

#include "app/loop/led_sink.h"
#include "app/show.h"
#include "devices/device.h"
#include "firmware_sim/sim_device.h"

#include <memory>
#include <vector>

namespace mar {

class LightRoute final : public LedSink {
 public:
  LightRoute(const ShowConfig& show, const std::vector<std::unique_ptr<SimDevice>>& sims, const std::unique_ptr<DeviceSet>& devices)
      : show_(show), sims_(sims), devices_(devices) {}
  bool send(uint16_t device, std::span<const uint8_t> message) override {
    if (device < sims_.size() && sims_[device] && device < show_.devices.size() && show_.devices[device].type == "sim")
      return sims_[device]->receive(message);
    if (devices_ && device < show_.devices.size()) return devices_->backend(device).send_midi(message);
    return false;
  }
  std::span<const uint8_t> last_sysex(uint16_t device, uint64_t& count) override {
    count = 0;
    if (!devices_ || device >= devices_->size()) return {};
    return devices_->last_sysex(device, count);
  }

 private:
  const ShowConfig& show_;
  const std::vector<std::unique_ptr<SimDevice>>& sims_;
  const std::unique_ptr<DeviceSet>& devices_;
};

}  // namespace mar
