// evdev input_events (pen tablets) -> Events: axes and stylus keys become HidValue events
// with the HID digitizer usages, so pen bindings are the same for evdev and hidraw tablets.
#include "input/decoder.h"
#include "input/evdev.h"
#include "input/hid_usages.h"

#include <cstring>

namespace mar {

uint32_t evdev::abs_usage(uint16_t code) {
  switch (code) {
    case kAbsX: return usage::kX;
    case kAbsY: return usage::kY;
    case kAbsZ: return usage::kZ;
    case kAbsWheel: return usage::kWheel;
    case kAbsPressure: return usage::kTipPressure;
    case kAbsTiltX: return usage::kXTilt;
    case kAbsTiltY: return usage::kYTilt;
    default: return 0;
  }
}

uint32_t evdev::key_usage(uint16_t code) {
  switch (code) {
    case kBtnTouch: return usage::kTipSwitch;
    case kBtnToolPen: return usage::kInRange;  // proximity
    case kBtnToolRubber: return usage::kEraser;
    case kBtnStylus: return usage::kBarrelSwitch;
    case kBtnStylus2: return usage::kSecondaryBarrelSwitch;
    default: return code >= kBtn0 && code <= kBtn9 ? usage::button(1 + uint32_t(code - kBtn0)) : 0;
  }
}

namespace {

class EvdevDecoder final : public Decoder {
 public:
  EvdevDecoder(std::vector<EvdevAxis> axes, uint16_t source) : Decoder(WireKind::EvdevEvent, source), axes_(std::move(axes)) {}

 private:
  void decode(const WireRecord& r, EventSink& out) override {
    if (r.size != 8) {
      malformed();
      return;
    }
    uint16_t type = 0, code = 0;
    int32_t value = 0;
    std::memcpy(&type, r.data, 2);
    std::memcpy(&code, r.data + 2, 2);
    std::memcpy(&value, r.data + 4, 4);
    Event e = event(r.t_ns, ControlKind::HidValue);
    e.value = value;
    if (type == evdev::kAbs) {
      e.number = evdev::abs_usage(code);
      for (const EvdevAxis& a : axes_)
        if (a.code == code) {
          e.lo = a.min;
          e.hi = a.max;
        }
    } else if (type == evdev::kKey) {
      e.number = evdev::key_usage(code);
      e.hi = 1;
      e.value = value != 0;
    }
    if (e.number != 0) out.push(e);
  }
  std::vector<EvdevAxis> axes_;
};

}  // namespace

WireRecord evdev_record(int64_t t, uint16_t type, uint16_t code, int32_t value, uint16_t source) {
  uint8_t b[8];
  std::memcpy(b, &type, 2);
  std::memcpy(b + 2, &code, 2);
  std::memcpy(b + 4, &value, 4);
  return WireRecord::make(t, WireKind::EvdevEvent, b, source);
}

std::unique_ptr<Decoder> make_evdev_decoder(std::vector<EvdevAxis> axes, uint16_t source) {
  return std::make_unique<EvdevDecoder>(std::move(axes), source);
}

}  // namespace mar
