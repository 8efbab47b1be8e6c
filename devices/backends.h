// The backends: one file pair each (usb_midi, hid, gpio, tablet, alsa_seq, osc, sdl), each
// built only when its CMake option is on (MARIONETTE_WITH_<NAME>). A backend left out is
// still known by type: it reports "not built" as its status instead of failing the show.
#pragma once

#include "devices/device.h"
#include "devices/discover.h"

#include <span>

namespace mar {

std::unique_ptr<Backend> make_usb_midi_backend(const DeviceSpec& s, uint16_t source);
std::unique_ptr<Backend> make_hid_backend(const DeviceSpec& s, uint16_t source);
std::unique_ptr<Backend> make_gpio_backend(const DeviceSpec& s, uint16_t source);
std::unique_ptr<Backend> make_tablet_backend(const DeviceSpec& s, uint16_t source);
std::unique_ptr<Backend> make_alsa_backend(const DeviceSpec& s, uint16_t source);
std::unique_ptr<Backend> make_audio_backend(const DeviceSpec& s, uint16_t source);  ///< ALSA capture
std::unique_ptr<Backend> make_osc_backend(const DeviceSpec& s, uint16_t source);
std::unique_ptr<Backend> make_sdl_backend(const DeviceSpec& s, uint16_t source);

BackendReport discover_usb_midi(const std::vector<ProfileId>& profiles);
BackendReport discover_hid(const std::vector<ProfileId>& profiles);
BackendReport discover_gpio(const std::vector<ProfileId>& profiles);
BackendReport discover_tablet(const std::vector<ProfileId>& profiles);
BackendReport discover_alsa(const std::vector<ProfileId>& profiles);
BackendReport discover_audio(const std::vector<ProfileId>& profiles);
BackendReport discover_sdl(const std::vector<ProfileId>& profiles);

/// One row per device type a show may name.
struct BackendInfo {
  const char* type;    ///< the show's `type =`
  const char* option;  ///< CMake option that builds it
  bool built;
  std::unique_ptr<Backend> (*make)(const DeviceSpec&, uint16_t);
  BackendReport (*discover)(const std::vector<ProfileId>&);  ///< nullptr: nothing to enumerate
  const char* note;    ///< status when there is nothing to enumerate
};
std::span<const BackendInfo> backend_table();
/// "not built (MARIONETTE_WITH_HID=OFF)"
std::string not_built_text(const BackendInfo& b);

/// The show window is open (mouse and touch are read over it). No-op without the SDL backend.
void sdl_input_window(bool open);

}  // namespace mar
