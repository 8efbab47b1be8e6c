// The show's state as outputs other than pictures see it (OSC out): where each rig handle is on
// the deformed character, each key's weight, each swap set's member, each trigger, each device's
// status, and the frame's time and input latency. Sized once (ShowStateLayout); the frame thread
// fills one a frame without allocating.
#pragma once

#include "geom/types.h"

#include <cstdint>
#include <string>
#include <vector>

namespace mar {

/// Names, fixed for a show: what each slot of a ShowState is.
struct ShowStateLayout {
  std::vector<std::string> handles, keys, swaps, triggers, devices;
  std::vector<std::vector<std::string>> swap_members;  ///< per swap set
  /// A cast's: each handle's, key's, swap set's and trigger's character (its address then
  /// starts with its name: /marionette/robot/handle/left-hand). Empty: a show's single rig.
  std::vector<std::string> handle_who, key_who, swap_who, trigger_who;
};

struct ShowState {
  uint64_t frame = 0;
  double t = 0;                      ///< show time, s
  std::vector<Vec2> handles;
  std::vector<double> keys;
  std::vector<int> swaps;            ///< the member shown, per set
  std::vector<uint8_t> triggers;     ///< 1: on
  std::vector<uint8_t> devices;      ///< DeviceState
  double frame_ms = 0, latency_ms = 0;  ///< this frame's compute; its newest input's age at frame-ready
  void size_for(const ShowStateLayout& l) {
    handles.assign(l.handles.size(), Vec2(0, 0));
    keys.assign(l.keys.size(), 0.0);
    swaps.assign(l.swaps.size(), 0);
    triggers.assign(l.triggers.size(), 0);
    devices.assign(l.devices.size(), 0);
  }
};

}  // namespace mar
