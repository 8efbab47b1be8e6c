// `marionette devices`, as a user runs it. The child
// process inherits umockdev's preload and this test's testbed, so it sees exactly the
// devices the bench presents (and none of the machine's).
#include "firmware_sim/hid_device.h"
#include "devices/vbench.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

namespace mar {
namespace {

// Profiles come from the data folder (MARIONETTE_DATA_DIR here); a broken one is named with
// its file and line and the rest still work.
TEST(DevicesCommand, ABrokenProfileIsNamedWithFileAndLine) {
  const auto dir = test::temp_dir("data");
  std::filesystem::create_directories(dir / "devices");
  std::filesystem::copy_file(test::source_dir() / "config/devices/ps4.toml", dir / "devices/ps4.toml");
  {
    std::ofstream f(dir / "devices/broken.toml");
    f << "[device]\nvid = = 3\n";
  }
  ::setenv("MARIONETTE_DATA_DIR", dir.c_str(), 1);
  const auto r = test::run_cli("devices --json");
  ::unsetenv("MARIONETTE_DATA_DIR");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("broken.toml:2:"), std::string::npos) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["data_dir"], dir.string());
  ASSERT_EQ(j["profile_errors"].size(), 1u);
}

TEST(DevicesCommand, NothingConnectedIsSaidPlainly) {
  VirtualBench bench;  // empty
  const auto r = test::run_cli("devices");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("No input devices found"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("hid: nothing found"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("alsa: no ALSA sequencer"), std::string::npos) << r.out;
  EXPECT_EQ(r.err.find("ALSA lib"), std::string::npos) << r.err;  // no library noise
  const auto j = nlohmann::json::parse(test::run_cli("devices --json").out);
  EXPECT_EQ(j["devices_found"], 0);
  EXPECT_EQ(j["backends"].size(), 8u);  // usb_midi, hid, gpio, tablet, alsa, audio, sdl, osc
}

TEST(DevicesCommand, ListsWhatEachBackendFindsWithProfileAndPermission) {
  VirtualBench bench;
  auto sim = make_sim_device("gamepad", "", 0, 1);
  ASSERT_TRUE(sim.ok());
  bench.add_hid({0x054c, 0x09cc, "Wireless Controller", "", static_cast<HidDeviceSim&>(**sim.value).descriptor_bytes()});
  bench.add_usb_midi({});
  bench.add_gpio({"pinctrl-bcm2711", {"GPIO17", "GPIO27"}});
  VirtualBench::Evdev pen;
  bench.add_evdev(pen);
  const auto j = nlohmann::json::parse(test::run_cli("devices --json").out);
  // SDL's own HID drivers recognise the pad too: it is listed by both backends.
  EXPECT_EQ(j["devices_found"], 5) << j.dump(1);
  std::map<std::string, nlohmann::json> by;
  for (const auto& b : j["backends"]) by[b["backend"]] = b;
  ASSERT_EQ(by["hid"]["found"].size(), 1u);
  EXPECT_EQ(by["hid"]["found"][0]["profile"], "ps4");
  EXPECT_EQ(by["hid"]["found"][0]["node"], "/dev/hidraw0");
  EXPECT_EQ(by["hid"]["found"][0]["status"], "available");
  EXPECT_NE(std::string(by["usb_midi"]["found"][0]["identity"]).find("0944:0117"), std::string::npos);
  EXPECT_NE(std::string(by["gpio"]["found"][0]["identity"]).find("'pinctrl-bcm2711' 2 lines"), std::string::npos);
  EXPECT_NE(std::string(by["tablet"]["found"][0]["identity"]).find("Virtual Pen Tablet"), std::string::npos);
  EXPECT_NE(std::string(by["sdl"]["found"][0]["identity"]).find("054c:09cc game controller"), std::string::npos);

}

}  // namespace
}  // namespace mar
