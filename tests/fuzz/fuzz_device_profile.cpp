// Device profiles (config/devices/NAME.toml): read through a show that names the profile,
// and through the VID/PID scan `marionette devices` makes.
#include "app/show.h"
#include "fuzz_util.h"

#include <cstdlib>
#include <filesystem>

namespace {
const std::string& folder() {
  static const std::string dir = [] {
    const std::string d = std::string(mar::fuzz::scratch_dir()) + "/marionette-fuzz-" + std::to_string(getpid());
    std::filesystem::create_directories(d + "/shows");
    std::filesystem::create_directories(d + "/devices");
    if (std::FILE* f = std::fopen((d + "/shows/show.toml").c_str(), "wb")) {
      std::fputs("[show]\nrig = \"r.toml\"\n[[device]]\nname = \"pad\"\nprofile = \"p\"\n"
                 "[[binding]]\ndevice = \"pad\"\ncontrol = \"left-x\"\ntarget = \"handle.head.x\"\n", f);
      std::fclose(f);
    }
    setenv("MARIONETTE_DATA_DIR", d.c_str(), 1);
    return d;
  }();
  return dir;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& dir = folder();
  if (std::FILE* f = std::fopen((dir + "/devices/p.toml").c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  const auto rig = [](const mar::ShowConfig&) {
    mar::ShowRig r;
    r.handles = {"head"};
    r.rest = {mar::Vec2(0, 0)};
    return mar::Result<mar::ShowRig>::success(r);
  };
  (void)mar::load_show(dir + "/shows/show.toml", rig);
  std::vector<std::string> errors;
  (void)mar::load_profile_ids(&errors);
  return 0;
}
