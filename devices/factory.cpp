// The table of backends and the stand-in for a backend this build left out.
#include "devices/backends.h"

#ifndef MARIONETTE_WITH_USB_MIDI
#define MARIONETTE_WITH_USB_MIDI 0
#endif
#ifndef MARIONETTE_WITH_HID
#define MARIONETTE_WITH_HID 0
#endif
#ifndef MARIONETTE_WITH_GPIO
#define MARIONETTE_WITH_GPIO 0
#endif
#ifndef MARIONETTE_WITH_TABLET
#define MARIONETTE_WITH_TABLET 0
#endif
#ifndef MARIONETTE_WITH_ALSA
#define MARIONETTE_WITH_ALSA 0
#endif
#ifndef MARIONETTE_WITH_OSC
#define MARIONETTE_WITH_OSC 0
#endif
#ifndef MARIONETTE_WITH_SDL
#define MARIONETTE_WITH_SDL 0
#endif

namespace mar {
namespace {

// A device type whose backend was not built: the show loads and runs, the device reports
// itself unavailable with the option that would build it.
class NotBuiltBackend final : public Backend {
 public:
  NotBuiltBackend(const DeviceSpec& s, uint16_t source, std::string why) : Backend(s, source) { problem_ = std::move(why); }
  DeviceState open() override { return DeviceState::Unavailable; }
  void close() override {}
  bool poll(int64_t, WireSink&) override { return true; }
};

#define MAR_BACKEND(type, NAME, make, discover, note)                                                   \
  BackendInfo {                                                                                         \
    type, "MARIONETTE_WITH_" #NAME, MARIONETTE_WITH_##NAME != 0, MARIONETTE_WITH_##NAME ? make : nullptr, \
        MARIONETTE_WITH_##NAME ? discover : nullptr, note                                               \
  }

#if !MARIONETTE_WITH_USB_MIDI
#define make_usb_midi_backend nullptr
#define discover_usb_midi nullptr
#endif
#if !MARIONETTE_WITH_HID
#define make_hid_backend nullptr
#define discover_hid nullptr
#endif
#if !MARIONETTE_WITH_GPIO
#define make_gpio_backend nullptr
#define discover_gpio nullptr
#endif
#if !MARIONETTE_WITH_TABLET
#define make_tablet_backend nullptr
#define discover_tablet nullptr
#endif
#if !MARIONETTE_WITH_ALSA
#define make_alsa_backend nullptr
#define make_audio_backend nullptr
#define discover_alsa nullptr
#define discover_audio nullptr
#endif
#if !MARIONETTE_WITH_OSC
#define make_osc_backend nullptr
#endif
#if !MARIONETTE_WITH_SDL
#define make_sdl_backend nullptr
#define discover_sdl nullptr
#endif

const BackendInfo kBackends[] = {
    MAR_BACKEND("usb_midi", USB_MIDI, make_usb_midi_backend, discover_usb_midi, ""),
    MAR_BACKEND("hid", HID, make_hid_backend, discover_hid, ""),
    MAR_BACKEND("gpio", GPIO, make_gpio_backend, discover_gpio, ""),
    MAR_BACKEND("tablet", TABLET, make_tablet_backend, discover_tablet, ""),
    MAR_BACKEND("alsa", ALSA, make_alsa_backend, discover_alsa, ""),
    MAR_BACKEND("audio", ALSA, make_audio_backend, discover_audio, ""),
    MAR_BACKEND("sdl", SDL, make_sdl_backend, discover_sdl, ""),
    MAR_BACKEND("osc", OSC, make_osc_backend, nullptr, "ok (listens on 127.0.0.1 when a show binds OSC addresses)"),
};

}  // namespace

std::span<const BackendInfo> backend_table() { return kBackends; }

std::string not_built_text(const BackendInfo& b) { return std::string("not built (") + b.option + "=OFF)"; }

std::unique_ptr<Backend> make_backend(const DeviceSpec& s, uint16_t source, std::string* error) {
  for (const BackendInfo& b : kBackends) {
    if (s.type != b.type) continue;
    if (!b.built) return std::make_unique<NotBuiltBackend>(s, source, "this marionette was built without the " + s.type +
                                                                           " backend: " + not_built_text(b));
    return b.make(s, source);
  }
  if (error) *error = "unknown device type '" + s.type + "' (sim, usb_midi, hid, gpio, tablet, alsa, audio, osc, sdl)";
  return nullptr;
}

#if !MARIONETTE_WITH_SDL
void sdl_input_window(bool) {}
#endif

}  // namespace mar
