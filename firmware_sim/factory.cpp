#include "firmware_sim/hid_device.h"
#include "firmware_sim/knob_box.h"
#include "firmware_sim/microphone.h"
#include "firmware_sim/midi_controller.h"

#include <filesystem>

namespace mar {
namespace {
// Built-in descriptors written for marionette, used when a show names no descriptor file:
// a pen (report 7: tip, in range, X/Y 0..32767, pressure 0..8191) and a 4-axis, 16-button
// gamepad. Shows normally name a real device's descriptor.
const uint8_t kBuiltinPen[] = {
    0x05, 0x0D, 0x09, 0x02, 0xA1, 0x01, 0x85, 0x07, 0x09, 0x20, 0xA1, 0x00, 0x09, 0x42, 0x09, 0x32,
    0x15, 0x00, 0x25, 0x01, 0x75, 0x01, 0x95, 0x02, 0x81, 0x02, 0x95, 0x06, 0x81, 0x03, 0x05, 0x01,
    0x09, 0x30, 0x09, 0x31, 0x15, 0x00, 0x26, 0xFF, 0x7F, 0x75, 0x10, 0x95, 0x02, 0x81, 0x02, 0x05,
    0x0D, 0x09, 0x30, 0x26, 0xFF, 0x1F, 0x95, 0x01, 0x81, 0x02, 0xC0, 0xC0};
const uint8_t kBuiltinGamepad[] = {
    0x05, 0x01, 0x09, 0x05, 0xA1, 0x01, 0x09, 0x30, 0x09, 0x31, 0x09, 0x32, 0x09, 0x35, 0x15, 0x00,
    0x26, 0xFF, 0x00, 0x75, 0x08, 0x95, 0x04, 0x81, 0x02, 0x05, 0x09, 0x19, 0x01, 0x29, 0x10, 0x15,
    0x00, 0x25, 0x01, 0x75, 0x01, 0x95, 0x10, 0x81, 0x02, 0xC0};
}  // namespace

Result<std::unique_ptr<SimDevice>> make_sim_device(const std::string& kind, const std::string& descriptor,
                                                   double bounce_ms, uint32_t seed) {
  using R = Result<std::unique_ptr<SimDevice>>;
  if (midi_model(kind)) return R::success(std::make_unique<MidiControllerSim>(kind));
  if (kind == "knob_box") return R::success(std::make_unique<KnobBoxSim>(bounce_ms, seed));
  if (kind == "microphone") {  // `descriptor`: the WAV it plays (the show resolves it)
    auto m = MicrophoneSim::make(descriptor, descriptor.empty() ? "" : std::filesystem::path(descriptor).parent_path().string());
    if (!m.ok()) return R::failure(m.error);
    return R::success(std::move(*m.value));
  }
  std::unique_ptr<HidDeviceSim> hid;
  std::span<const uint8_t> builtin;
  if (kind == "pen_tablet") {
    hid = std::make_unique<PenTabletSim>();
    builtin = kBuiltinPen;
  } else if (kind == "gamepad") {
    hid = std::make_unique<GamepadSim>();
    builtin = kBuiltinGamepad;
  } else {
    return R::failure("unknown simulated device '" + kind + "' (" + midi_model_names() + ", knob_box, pen_tablet, gamepad, microphone)");
  }
  std::vector<uint8_t> bytes(builtin.begin(), builtin.end());
  if (!descriptor.empty()) {
    auto file = read_descriptor_file(descriptor);
    if (!file.ok()) return R::failure(file.error);
    bytes = std::move(*file.value);
  }
  if (auto ok = hid->set_descriptor(bytes); !ok.ok()) return R::failure(descriptor + ": " + ok.error);
  const bool pen = kind == "pen_tablet";
  const bool complete = hid->has(usage::X) && hid->has(usage::Y) && (!pen || hid->has(usage::TipSwitch));
  if (!complete)
      return R::failure(descriptor + ": the descriptor has no " + (pen ? "pen X, Y and tip switch" : "stick X and Y") +
                        " input usages");
  return R::success(std::move(hid));
}

}  // namespace mar
