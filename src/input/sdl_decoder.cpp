// SDL controls (game controllers, the mouse and touch over the show window) -> HidValue
// events with the usages a hidraw device would give (X/Y, tip switch, buttons), so the same
// bindings work.
#include "input/decoder.h"
#include "input/hid_usages.h"

#include <cstring>

namespace mar {
namespace {

// SDL_GameControllerAxis order: left X/Y, right X/Y, left/right trigger.
constexpr uint32_t kAxisUsage[6] = {usage::kX, usage::kY, usage::kZ, usage::kRz, usage::kRx, usage::kRy};

class SdlDecoder final : public Decoder {
 public:
  explicit SdlDecoder(uint16_t source) : Decoder(WireKind::SdlControl, source) {}

 private:
  void decode(const WireRecord& r, EventSink& out) override {
    if (r.size != 14) {
      malformed();
      return;
    }
    const auto what = SdlWhat(r.data[0]);
    const uint8_t index = r.data[1];
    Event e = event(r.t_ns, ControlKind::HidValue);
    std::memcpy(&e.value, r.data + 2, 4);
    std::memcpy(&e.lo, r.data + 6, 4);
    std::memcpy(&e.hi, r.data + 10, 4);
    switch (what) {
      case SdlWhat::PadAxis:
        if (index >= std::size(kAxisUsage)) return malformed();
        e.number = kAxisUsage[index];
        break;
      case SdlWhat::PadButton: e.number = usage::button(1 + uint32_t(index)); break;
      case SdlWhat::MouseX:
      case SdlWhat::TouchX: e.number = usage::kX; break;
      case SdlWhat::MouseY:
      case SdlWhat::TouchY: e.number = usage::kY; break;
      case SdlWhat::MouseButton: e.number = index == 0 ? usage::kTipSwitch : usage::button(1 + uint32_t(index)); break;
      case SdlWhat::Touching: e.number = usage::kTipSwitch; break;
      default: return malformed();
    }
    out.push(e);
  }
};

}  // namespace

std::unique_ptr<Decoder> make_sdl_decoder(uint16_t source) { return std::make_unique<SdlDecoder>(source); }

/// An SdlControl record (the SDL backend writes these; tests too).
WireRecord sdl_record(int64_t t, SdlWhat what, uint8_t index, int32_t value, int32_t lo, int32_t hi, uint16_t source) {
  uint8_t b[14];
  b[0] = uint8_t(what);
  b[1] = index;
  std::memcpy(b + 2, &value, 4);
  std::memcpy(b + 6, &lo, 4);
  std::memcpy(b + 10, &hi, 4);
  return WireRecord::make(t, WireKind::SdlControl, b, source);
}

}  // namespace mar
