// Show files (TOML): [show], devices (sim and hardware), groups, poses, bindings, [kiosk], a
// cast ([[character]]), resolved against a fixed rig, or a cast of copies of it named as the
// show names them (the rig loader is not what is fuzzed here).
#include "app/show.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = mar::fuzz::scratch_file("show.toml", mar::fuzz::text(data, size));
  const auto rig = [](const mar::ShowConfig& header) {
    mar::ShowRig r;
    r.handles = {"head", "hand_l", "hand_r"};
    r.rest = {mar::Vec2(0, 0), mar::Vec2(-1, 1), mar::Vec2(1, 1)};
    r.diag = 10;
    r.settings = {{"iterations", std::pair{1.0, 30.0}}, {"stiffness", std::nullopt}};
    r.swaps = {{"mouth", {"open", "shut"}}};
    r.triggers = {"blink"};
    r.keys = {"wave"};
    if (header.cast.empty()) return mar::Result<mar::ShowRig>::success(r);
    std::vector<std::string> names;
    for (const mar::ShowCharacter& c : header.cast) names.push_back(c.name);
    return mar::Result<mar::ShowRig>::success(mar::cast_rig(names, std::vector<mar::ShowRig>(names.size(), r)));
  };
  (void)mar::load_show(path, rig);
  return 0;
}
