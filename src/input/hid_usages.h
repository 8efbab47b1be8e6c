// The HID usages marionette names (page << 16 | id, HID Usage Tables 1.4): one table for the
// control grammar ("usage x"), the mapping's pointer defaults and the backends that turn
// evdev axes, SDL controllers, mice and touch into HID usages.
#pragma once

#include <cstdint>

namespace mar::usage {

// Generic Desktop (page 0x01)
constexpr uint32_t kX = 0x010030, kY = 0x010031, kZ = 0x010032, kRx = 0x010033, kRy = 0x010034, kRz = 0x010035;
constexpr uint32_t kDial = 0x010037, kWheel = 0x010038, kHatSwitch = 0x010039;
// Digitizers (page 0x0D)
constexpr uint32_t kTipPressure = 0x0D0030, kInRange = 0x0D0032, kXTilt = 0x0D003D, kYTilt = 0x0D003E;
constexpr uint32_t kTipSwitch = 0x0D0042, kBarrelSwitch = 0x0D0044, kEraser = 0x0D0045, kSecondaryBarrelSwitch = 0x0D005A;
// Button (page 0x09): button n is kButtonPage << 16 | n
constexpr uint32_t kButtonPage = 0x09;
constexpr uint32_t button(uint32_t n) { return kButtonPage << 16 | n; }

struct Name {
  const char* name;
  uint32_t usage;
};
/// Names of the control grammar (`usage NAME`).
inline constexpr Name kNames[] = {{"x", kX},          {"y", kY},           {"z", kZ},
                                  {"rx", kRx},        {"ry", kRy},         {"rz", kRz},
                                  {"dial", kDial},    {"wheel", kWheel},   {"hat", kHatSwitch},
                                  {"pressure", kTipPressure}, {"in_range", kInRange}, {"tip", kTipSwitch},
                                  {"barrel", kBarrelSwitch},  {"x_tilt", kXTilt},     {"y_tilt", kYTilt}};

}  // namespace mar::usage
