// Device profiles (config/devices/): every control a profile names parses, and where the
// profile names a real report descriptor from the corpus, the usage is in that descriptor.
#include "app/show.h"
#include "firmware_sim/hid_device.h"
#include "firmware_sim/midi_controller.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <toml++/toml.h>

#include <fstream>

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
  EXPECT_EQ(profiles, 11);
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

// Every MIDI controller's profile and its simulator (firmware_sim/midi_models.cpp, written from
// the makers' MIDI maps) agree: the same controls by name, each the same note or CC on the same
// channel; and each light the profile sends, on and off, is what lights and darkens that
// control's LED in the simulator (rings: ringN from the ring's low to its high end).
TEST(DeviceProfiles, EveryMidiProfileAgreesWithItsSimulatorOnControlsAndLights) {
  int profiles = 0;
  for (const char* name : {"nanokontrol2", "apc_mini_mk2", "midimix", "launch_control_xl", "xtouch_mini", "beatstep"}) {
    SCOPED_TRACE(name);
    const std::string file = (test::source_dir() / "config/devices" / (std::string(name) + ".toml")).string();
    ShowDevice d;
    d.name = name;
    ASSERT_NO_THROW(read_hardware_profile(file, name, d));
    EXPECT_EQ(d.sim, name);
    EXPECT_EQ(d.hw.type, "usb_midi");
    MidiControllerSim sim(name);
    if (std::string(name) == "nanokontrol2") {
      ASSERT_TRUE(sim.load_script("0 ledmode external").ok());
    }
    EXPECT_EQ(d.controls.size(), sim.controls().size());
    for (const auto& [cname, text] : d.controls) {
      ControlSpec c;
      ASSERT_TRUE(parse_control(text, c).ok()) << cname;
      const MidiControl* m = sim.control(cname);
      ASSERT_NE(m, nullptr) << cname << " is not a control of the simulator";
      EXPECT_EQ(m->note, c.kind == ControlSpec::Note) << cname;
      EXPECT_EQ(m->number, int(c.number)) << cname;
      EXPECT_EQ(m->channel, c.channel < 0 ? 0 : c.channel) << cname;
    }
    EXPECT_FALSE(d.leds.empty());
    int ring = 0;
    for (const DeviceLed& l : d.leds) {
      const std::string shown = l.ring ? "ring" + std::to_string(++ring) : l.name;
      for (int v : {l.ring ? l.hi : l.on, l.ring ? l.lo : l.off}) {
        std::vector<uint8_t> msg = l.bytes;
        msg[l.value_at] = uint8_t(v);
        EXPECT_TRUE(sim.receive(msg)) << l.name;
        EXPECT_EQ(sim.led(shown), v) << l.name;
      }
    }
    EXPECT_EQ(sim.ignored(), 0u);
    ++profiles;
  }
  EXPECT_EQ(profiles, 6);
  // The nanoKONTROL2 lights only in its External LED mode (a stored scene setting).
  MidiControllerSim internal("nanokontrol2");
  const uint8_t solo1[] = {0xB0, 32, 127};
  EXPECT_FALSE(internal.receive(solo1));
  EXPECT_EQ(internal.led("solo1"), -1);
}

// Where Ardour ships a map of the same controller (the shared corpus: an independent source),
// every note and CC it binds on its channel is a control of the profile.
TEST(DeviceProfiles, ArdoursMapsBindOnlyControlsTheProfilesHave) {
  const auto dir = test::corpus_dir() / "midi" / "ardour-midi-maps";
  if (!std::filesystem::is_directory(dir)) GTEST_SKIP() << "the shared corpus is not here (" << dir << ")";
  const std::pair<const char*, const char*> maps[] = {{"apc_mini_mk2", "AKAI_APCmini_mk2.map"},
                                                      {"midimix", "AKAI_MIDIMix_Normal_Mode.map"},
                                                      {"launch_control_xl", "Novation_LaunchControl_XL.map"},
                                                      {"nanokontrol2", "Korg_nanoKONTROL2.map"}};
  for (const auto& [profile, map] : maps) {
    SCOPED_TRACE(profile);
    ShowDevice d;
    read_hardware_profile((test::source_dir() / "config/devices" / (std::string(profile) + ".toml")).string(), profile, d);
    std::ifstream in(dir / map);
    ASSERT_TRUE(in) << map;
    const std::string xml((std::istreambuf_iterator<char>(in)), {});
    int bindings = 0;
    for (size_t at = xml.find("<Binding"); at != std::string::npos; at = xml.find("<Binding", at + 1)) {
      const std::string tag = xml.substr(at, xml.find('>', at) - at);
      auto attr = [&](const std::string& k) {
        const size_t p = tag.find(" " + k + "=\"");
        return p == std::string::npos ? -1 : std::atoi(tag.c_str() + p + k.size() + 3);
      };
      const int ch = attr("channel"), ctl = attr("ctl"), note = attr("note");
      if (ch < 1 || (ctl < 0 && note < 0)) continue;
      bool found = false;
      for (const auto& [name, text] : d.controls) {
        ControlSpec c;
        if (!parse_control(text, c).ok()) continue;
        const int cch = c.channel < 0 ? 0 : c.channel;
        found = found || (cch == ch - 1 && int(c.number) == (ctl >= 0 ? ctl : note) &&
                          (ctl >= 0 ? c.kind == ControlSpec::CC : c.kind == ControlSpec::Note));
      }
      EXPECT_TRUE(found) << map << ": " << tag;
      ++bindings;
    }
    EXPECT_GT(bindings, 8) << map;
  }
}

}  // namespace
}  // namespace mar
