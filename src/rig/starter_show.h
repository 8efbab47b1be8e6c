// A starter show for an automatic rig: its limbs, body, head, swap sets and triggers on one
// device's controls, with a timeline script so it moves at once with the device's simulator
// (the same bindings work with the real device: change the [[device]] table as Devices says).
#pragma once

#include "base/result.h"
#include "rig/auto_rig.h"

#include <string>

namespace mar {

/// The devices a starter show can be written for.
inline constexpr const char* kStarterDevices[] = {"nanokontrol2", "gamepad", "pen_tablet", "knob_box"};

/// The show as commented TOML. `rig_path`: the rig file as the show should name it (relative
/// to the show's folder). An unknown device is an error naming the ones there are.
Result<std::string> starter_show(const AutoRig& a, const Character& ch, const std::string& rig_path, const std::string& device);

}  // namespace mar
