// Factories of the hardware backends (one file each) and the pieces tests reach into.
#pragma once

#include "devices/device.h"

#include <lo/lo_osc_types.h>

namespace mar {

std::unique_ptr<Backend> make_usb_midi_backend(const DeviceSpec& s, uint16_t source);
std::unique_ptr<Backend> make_hid_backend(const DeviceSpec& s, uint16_t source);
std::unique_ptr<Backend> make_gpio_backend(const DeviceSpec& s, uint16_t source);
std::unique_ptr<Backend> make_tablet_backend(const DeviceSpec& s, uint16_t source);
std::unique_ptr<Backend> make_alsa_backend(const DeviceSpec& s, uint16_t source);
std::unique_ptr<Backend> make_osc_backend(const DeviceSpec& s, uint16_t source);
std::unique_ptr<Backend> make_sdl_backend(const DeviceSpec& s, uint16_t source);

/// The show window is open (mouse and touch are read over it).
void sdl_input_window(bool open);

/// OSC: the Event for a message at `path` whose arguments are `types`/`argv`; returns the
/// index of the first pattern in `patterns` that matches, or -1 (no event).
int osc_event(const std::vector<std::string>& patterns, const char* path, const char* types, lo_arg** argv, Event& e);

}  // namespace mar
