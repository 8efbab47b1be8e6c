// The window's heads-up display: a bar for the share of the frame budget the last frame
// used (green below half, amber, red above 80%) and a box per show device for its state
// (green connected or simulated, amber waiting, red unplugged or denied, grey unavailable).
#pragma once

#include "devices/device.h"
#include "render/canvas.h"

#include <span>

namespace mar {

void draw_hud(Canvas& canvas, double used_us, double budget_us, std::span<const DeviceState> devices);

}  // namespace mar
