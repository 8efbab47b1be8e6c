// Show files (TOML): [show], devices (sim and hardware), groups, poses, bindings, [kiosk],
// resolved against a fixed rig (the rig loader is not what is fuzzed here).
#include "app/show.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = mar::fuzz::scratch_file("show.toml", mar::fuzz::text(data, size));
  const auto rig = [](const mar::ShowConfig&) {
    mar::ShowRig r;
    r.handles = {"head", "hand_l", "hand_r"};
    r.rest = {mar::Vec2(0, 0), mar::Vec2(-1, 1), mar::Vec2(1, 1)};
    r.diag = 10;
    r.settings = {{"iterations", std::pair{1.0, 30.0}}, {"stiffness", std::nullopt}};
    r.swaps = {{"mouth", {"open", "shut"}}};
    r.triggers = {"blink"};
    r.keys = {"wave"};
    return mar::Result<mar::ShowRig>::success(r);
  };
  (void)mar::load_show(path, rig);
  return 0;
}
