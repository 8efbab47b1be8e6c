// An in-process simulated device as an input source: it sits in the show's DeviceSet like
// a hardware backend, always connected, and yields the wire records its timeline holds.
#pragma once

#include "devices/device.h"
#include "firmware_sim/sim_device.h"

namespace mar {

class SimSource final : public Backend {
 public:
  /// `debounce_ns`: the receiver's GPIO debounce (a knob box read through a debouncer).
  /// `sim` must outlive the source.
  SimSource(SimDevice& sim, const DeviceSpec& spec, uint16_t source, int64_t debounce_ns);
  DeviceState open() override;
  void close() override {}
  bool poll(int64_t now_ns, WireSink& out) override;

 private:
  SimDevice* sim_;
  int64_t debounce_ns_ = 0;
};

}  // namespace mar
