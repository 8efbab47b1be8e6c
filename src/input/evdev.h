// The evdev event codes a pen tablet uses, by value (the kernel ABI of
// linux/input-event-codes.h; a test checks them against the header), and their HID usages.
#pragma once

#include <cstdint>

namespace mar::evdev {

inline constexpr uint16_t kSyn = 0x00, kKey = 0x01, kAbs = 0x03;
inline constexpr uint16_t kAbsX = 0x00, kAbsY = 0x01, kAbsZ = 0x02, kAbsWheel = 0x08, kAbsPressure = 0x18,
                          kAbsTiltX = 0x1a, kAbsTiltY = 0x1b;
inline constexpr uint16_t kBtn0 = 0x100, kBtn9 = 0x109, kBtnToolPen = 0x140, kBtnToolRubber = 0x141, kBtnTouch = 0x14a,
                          kBtnStylus = 0x14b, kBtnStylus2 = 0x14c;

/// evdev absolute axis -> HID usage (page << 16 | id); 0 when unused.
uint32_t abs_usage(uint16_t code);
/// evdev key -> HID usage; 0 when unused.
uint32_t key_usage(uint16_t code);

}  // namespace mar::evdev
