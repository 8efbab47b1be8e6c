// Device profiles (config/devices/): every control a profile names parses and is in the
// descriptor the profile ships, and in the real device's descriptor where the corpus has it.
#include "app/show.h"
#include "firmware_sim/hid_device.h"
#include "firmware_sim/midi_controller.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <toml++/toml.h>

#include <fstream>
#include <map>

namespace mar {
namespace {

// Every HID profile ships the descriptor its simulator presents (config/devices/descriptors:
// composed for this project, nothing read from the corpus), every control's usage is in it, and
// where the shared corpus has the real device's descriptor (an independent source) each control
// is there too, in the same report at the same bits, with the same range.
TEST(DeviceProfiles, ControlsParseAndExistInTheShippedAndTheRealDescriptor) {
  const std::map<std::string, std::string> real = {
      {"ps4", "hid/hid-tools-descriptors/sony_gamepad__PS4ControllerUSB.hex"},
      {"ps5", "hid/hid-tools-descriptors/sony_gamepad__PS5ControllerUSB.hex"},
      {"surface_dial", "hid/udev-hid-bpf/descriptors/Microsoft__Surface_Dial__block0.hex"}};
  auto parse = [](const std::filesystem::path& file) {
    auto bytes = read_descriptor_file(file.string());
    EXPECT_TRUE(bytes.ok()) << file << ": " << bytes.error;
    auto parsed = bytes.ok() ? parse_hid_descriptor(*bytes.value) : Result<HidDescriptor>::failure("unread");
    EXPECT_TRUE(parsed.ok()) << file << ": " << parsed.error;
    return parsed.ok() ? *parsed.value : HidDescriptor{};
  };
  int profiles = 0, checked = 0, against_real = 0;
  for (const auto& e : std::filesystem::directory_iterator(test::source_dir() / "config/devices")) {
    if (e.path().extension() != ".toml") continue;
    const toml::table t = toml::parse_file(e.path().string());
    const std::string name = e.path().stem().string();
    ++profiles;
    HidDescriptor desc, truth;
    bool have = false, have_truth = false;
    if (auto d = t["device"]["descriptor"].value<std::string>()) {
      EXPECT_NE(d->rfind("corpus:", 0), 0u) << name << ": a shipped profile uses only what ships";
      desc = parse(e.path().parent_path() / *d);
      have = true;
      if (auto it = real.find(name); it != real.end() && std::filesystem::exists(test::corpus_dir() / it->second)) {
        truth = parse(test::corpus_dir() / it->second);
        have_truth = true;
      }
    }
    const toml::table* controls = t["controls"].as_table();
    ASSERT_NE(controls, nullptr) << e.path();
    for (const auto& [cname, v] : *controls) {
      ControlSpec c;
      const std::string text = v.value_or(std::string());
      ASSERT_TRUE(parse_control(text, c).ok()) << e.path() << ": " << cname.str() << " = " << text;
      if (!have || c.kind != ControlSpec::Hid) continue;
      int k = 0, kt = 0;
      const HidField* f = desc.find_usage(c.number, &k);
      ASSERT_NE(f, nullptr) << name << ": " << cname.str() << " = " << text;
      ++checked;
      if (!have_truth) continue;
      const HidField* g = truth.find_usage(c.number, &kt);
      ASSERT_NE(g, nullptr) << name << ": " << cname.str() << " is not in the real descriptor";
      EXPECT_EQ(f->report_id, g->report_id) << name << ": " << cname.str();
      EXPECT_EQ(f->bit_offset + uint32_t(k) * f->bit_size, g->bit_offset + uint32_t(kt) * g->bit_size) << name << ": " << cname.str();
      EXPECT_EQ(f->bit_size, g->bit_size) << name << ": " << cname.str();
      EXPECT_EQ(f->logical_min, g->logical_min) << name << ": " << cname.str();
      EXPECT_EQ(f->logical_max, g->logical_max) << name << ": " << cname.str();
      EXPECT_EQ(f->is_relative(), g->is_relative()) << name << ": " << cname.str();
      ++against_real;
    }
  }
  EXPECT_EQ(profiles, 11);
  EXPECT_GE(checked, 20);  // ps4, ps5 and the dial
  if (std::filesystem::exists(test::corpus_dir())) {
    EXPECT_GE(against_real, 20);
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
