// Device profiles (config/devices/): every control a profile names parses, and where the
// profile names a real report descriptor from the corpus, the usage is in that descriptor.
#include "app/show.h"
#include "firmware_sim/hid_device.h"
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
  EXPECT_EQ(profiles, 5);
  if (std::filesystem::exists(test::corpus_dir())) {
    EXPECT_GE(checked, 20);  // ps4, ps5 and the dial
  }
}

}  // namespace
}  // namespace mar
