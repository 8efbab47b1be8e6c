// Device profiles (config/devices/): every control a profile names parses, and where the
// profile names a real report descriptor from the corpus, the usage is in that descriptor.
#include "app/show.h"
#include "firmware_sim/hid_device.h"
#include "firmware_sim/midi_controller.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <toml++/toml.h>

namespace mar {
namespace {

TEST(DeviceProfiles, ControlsParseAndExistInTheRealDescriptor) {
  int profiles = 0, checked = 0;
  for (const auto& e : std::filesystem::directory_iterator(test::source_dir() / "config/devices")) {
    const toml::table t = toml::parse_file(e.path().string());
    ++profiles;
    HidDescriptor desc;
    bool have = false;
    if (auto d = t["device"]["descriptor"].value<std::string>()) {
      const auto file = test::corpus_dir() / d->substr(7);
      if (std::filesystem::exists(file)) {
        auto bytes = read_descriptor_file(file.string());
        ASSERT_TRUE(bytes.ok()) << file;
        auto parsed = parse_hid_descriptor(*bytes.value);
        ASSERT_TRUE(parsed.ok()) << file << ": " << parsed.error;
        desc = *parsed.value;
        have = true;
      }
    }
    const toml::table* controls = t["controls"].as_table();
    ASSERT_NE(controls, nullptr) << e.path();
    for (const auto& [name, v] : *controls) {
      ControlSpec c;
      const std::string text = v.value_or(std::string());
      ASSERT_TRUE(parse_control(text, c).ok()) << e.path() << ": " << name.str() << " = " << text;
      if (have && c.kind == ControlSpec::Hid) {
        EXPECT_NE(desc.find_usage(c.number), nullptr) << e.path().filename() << ": " << name.str() << " = " << text;
        ++checked;
      }
    }
  }
  EXPECT_EQ(profiles, 6);
  if (std::filesystem::exists(test::corpus_dir())) {
    EXPECT_GE(checked, 20);  // ps4, ps5 and the dial
  }
}

// The nanoKONTROL2's profile and its simulator speak of the same controls: every control the
// profile names is the CC the simulator sends for that name, and the simulator has no control
// the profile leaves out.
TEST(DeviceProfiles, TheNanoKontrol2ProfileAgreesWithItsSimulator) {
  const toml::table t = toml::parse_file((test::source_dir() / "config/devices/nanokontrol2.toml").string());
  EXPECT_EQ(t["device"]["type"].value_or(std::string()), "usb_midi");
  EXPECT_EQ(t["device"]["vid"].value_or(0), 0x0944);
  EXPECT_EQ(t["device"]["pid"].value_or(0), 0x0117);
  EXPECT_EQ(t["device"]["sim"].value_or(std::string()), "nanokontrol2");
  const toml::table* controls = t["controls"].as_table();
  ASSERT_NE(controls, nullptr);
  int n = 0;
  for (const auto& [name, v] : *controls) {
    ControlSpec c;
    ASSERT_TRUE(parse_control(v.value_or(std::string()), c).ok()) << name.str();
    EXPECT_EQ(c.kind, ControlSpec::CC) << name.str();
    EXPECT_EQ(int(c.number), MidiControllerSim::cc_of(std::string(name.str()))) << name.str();
    ++n;
  }
  EXPECT_EQ(n, 8 * 5 + 11) << "five strips of eight and eleven transport buttons";
}

}  // namespace
}  // namespace mar
