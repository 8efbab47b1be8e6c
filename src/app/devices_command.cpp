// `marionette devices [--json]`: every backend, what it finds, status and problems.
#include "app/commands.h"
#include "app/show.h"
#include "render/canvas.h"

#include <nlohmann/json.hpp>

#include <iostream>

namespace mar {

int cmd_devices(const DevicesArgs& a) {
  std::vector<std::string> profile_errors;
  const auto reports = discover_devices(load_profile_ids(&profile_errors));
  for (const std::string& e : profile_errors) std::cerr << "error: device profile " << e << "\n";
  size_t total = 0;
  for (const auto& r : reports) total += r.found.size();
  // The screens a show's window may open on ([display] screen = index or a name's part).
  std::string screen_error;
  const std::vector<ScreenInfo> screens = list_screens(&screen_error);
  if (a.json) {
    nlohmann::ordered_json sj = nlohmann::ordered_json::array();
    for (const ScreenInfo& s : screens)
      sj.push_back({{"index", s.index}, {"name", s.name}, {"width", s.width}, {"height", s.height}});
    nlohmann::ordered_json j = nlohmann::ordered_json::array();
    for (const auto& r : reports) {
      nlohmann::ordered_json found = nlohmann::ordered_json::array();
      for (const auto& f : r.found)
        found.push_back({{"identity", f.identity}, {"node", f.node}, {"profile", f.profile}, {"status", f.status},
                         {"problem", f.problem}});
      j.push_back({{"backend", r.backend}, {"status", r.status}, {"found", found}});
    }
    std::cout << nlohmann::ordered_json{{"devices_found", total}, {"data_dir", data_dir()}, {"profile_errors", profile_errors},
                                        {"backends", j}, {"screens", sj}, {"screens_problem", screen_error}}
                     .dump(2)
              << "\n";
    return 0;
  }
  if (total == 0)
    std::cout << "No input devices found: no USB-MIDI controller, HID device, GPIO chip, pen tablet, ALSA MIDI "
                 "port or game controller is connected (or visible to this user).\n"
                 "Shows still run with simulated devices: marionette run SHOW.toml --simulate\n\n";
  for (const auto& r : reports) {
    std::cout << r.backend << ": ";
    if (r.status != "ok") std::cout << r.status;
    else if (r.found.empty()) std::cout << "nothing found";
    else std::cout << r.found.size() << " found";
    std::cout << "\n";
    for (const auto& f : r.found) {
      std::cout << "  " << f.identity << "  " << f.node << "  [" << f.status << "]";
      if (!f.profile.empty()) std::cout << "  profile " << f.profile;
      if (!f.problem.empty()) std::cout << "  -- " << f.problem;
      std::cout << "\n";
    }
  }
  std::cout << "screens: ";
  if (screens.empty()) std::cout << (screen_error.empty() ? "none" : screen_error) << "\n";
  else std::cout << screens.size() << " ([display] screen = index or part of the name)\n";
  for (const ScreenInfo& s : screens) std::cout << "  " << s.index << "  " << s.name << "  " << s.width << "x" << s.height << "\n";
  return 0;
}

}  // namespace mar
