// `marionette devices`: what each backend can see on this machine, without claiming it.
#pragma once

#include <string>
#include <vector>

namespace mar {

struct FoundDevice {
  std::string backend;   ///< usb_midi | hid | gpio | tablet | alsa | sdl
  std::string identity;  ///< VID:PID and name, chip and label, ...
  std::string node;      ///< device node
  std::string profile;   ///< matched config/devices profile
  std::string status;    ///< "available", "permission denied", ...
  std::string problem;   ///< one line when not available
};

struct ProfileId {
  std::string name;
  int vid = -1;
  std::vector<int> pids;
};

struct BackendReport {
  std::string backend;
  std::string status;    ///< "ok" or why the backend cannot look ("no /dev/snd/seq")
  std::vector<FoundDevice> found;
};

/// Looks with every backend. `profiles` name known devices by VID/PID.
std::vector<BackendReport> discover_devices(const std::vector<ProfileId>& profiles);

}  // namespace mar
