#include "devices/backends.h"

namespace mar {

std::unique_ptr<Backend> make_backend(const DeviceSpec& s, uint16_t source, std::string* error) {
  if (s.type == "usb_midi") return make_usb_midi_backend(s, source);
  if (s.type == "hid") return make_hid_backend(s, source);
  if (s.type == "gpio") return make_gpio_backend(s, source);
  if (s.type == "tablet") return make_tablet_backend(s, source);
  if (s.type == "alsa") return make_alsa_backend(s, source);
  if (s.type == "osc") return make_osc_backend(s, source);
  if (s.type == "sdl") return make_sdl_backend(s, source);
  if (error) *error = "unknown device type '" + s.type + "' (sim, usb_midi, hid, gpio, tablet, alsa, osc, sdl)";
  return nullptr;
}

}  // namespace mar
