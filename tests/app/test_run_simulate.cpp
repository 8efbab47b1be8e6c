// Whole hardware shows run on the virtual bench through `marionette run --simulate` (the
// child process inherits umockdev's preload and this test's testbed), and their recordings.
// Built into test_devices, whose main sets up the bench.
#include "firmware_sim/sim_device.h"
#include "input/decoder.h"
#include "app/loop/recording.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include <filesystem>
#include <fstream>
#include <map>

namespace mar {
namespace {

const std::string kHardwareShow = "config/shows/hardware.toml";

// The records each device of the hardware show writes: its simulator's timeline, made from the
// show file's script as the show makes it (the pen's HID reports become evdev events, so it is
// left out: -1).
std::vector<long> scripted_records(const std::string& show) {
  std::vector<long> n;
  const toml::table t = toml::parse_file(show);
  for (const auto& node : *t["device"].as_array()) {
    const toml::table& d = *node.as_table();
    std::string sim = d["sim"].value_or(std::string());
    std::string descriptor;
    if (d["profile"].value_or(std::string()) == "nanokontrol2") sim = "nanokontrol2";  // the profile's simulator
    if (d["profile"].value_or(std::string()) == "ps4") {  // the profile's simulator and descriptor
      sim = "gamepad";
      const auto p = test::corpus_dir() / "hid/hid-tools-descriptors/sony_gamepad__PS4ControllerUSB.hex";
      if (std::filesystem::exists(p)) descriptor = p.string();
    }
    if (d["type"].value_or(std::string()) == "tablet") {
      n.push_back(-1);
      continue;
    }
    auto dev = make_sim_device(sim, descriptor, d["bounce_ms"].value_or(0.0), uint32_t(d["seed"].value_or(1)));
    EXPECT_TRUE(dev.ok()) << dev.error;
    if (!dev.ok()) return {};
    EXPECT_TRUE((*dev.value)->load_script(d["script"].value_or(std::string())).ok());
    n.push_back(long((*dev.value)->timeline().size()));
  }
  return n;
}

nlohmann::json run_hardware_show(const std::string& name) {
  const auto stats = test::temp_dir("simulate") / (name + ".json");
  const auto r = test::run_cli("run '" + (test::source_dir() / kHardwareShow).string() + "' --headless --simulate --stats '" +
                               stats.string() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(stats);
  return r.exit_code == 0 ? nlohmann::json::parse(in) : nlohmann::json();
}

// Every record the scripts produce arrives through the real backends, exactly: the players
// write in lockstep with the show's virtual clock, and a frame waits until the bench has
// written through its time (it failed on a busy machine when players wrote on the wall clock).
TEST(RunSimulate, HardwareShowRunsOnTheBenchWithEveryBackend) {
  const auto j = run_hardware_show("exact");
  ASSERT_EQ(j["devices"].size(), 4u);
  for (const auto& d : j["devices"]) {
    EXPECT_EQ(d["status"], "connected") << d.dump();
    EXPECT_GT(d["events"], 0) << d.dump();
    EXPECT_EQ(d["malformed"], 0) << d.dump();
  }
  std::vector<long> want = scripted_records((test::source_dir() / kHardwareShow).string());
  ASSERT_EQ(want.size(), 4u);
  // The nanoKONTROL2 also answers the three scene requests that set its LED mode: a search reply,
  // its scene (402 bytes: 134 packets in six records) and an ACK.
  want[0] += 1 + 6 + 1;
  EXPECT_EQ(j["leds"]["korg_led_mode"], "switched");
  for (size_t i = 0; i < 4; ++i) {
    if (want[i] >= 0) {
      EXPECT_EQ(j["devices"][i]["records"].get<long>(), want[i]) << j["devices"][i].dump();
    }
  }
  EXPECT_EQ(j["devices"][0]["node"], "/dev/bus/usb/001/002");
  EXPECT_EQ(j["devices"][2]["events"], 40);  // two encoders, 20 detents each
  EXPECT_EQ(j["heap_allocations_after_warmup"], 0);
  EXPECT_EQ(j["grabs"]["count"], 2);  // the pen grabbed and let go, twice
  EXPECT_EQ(j["clock"]["mode"], "virtual");
  EXPECT_EQ(j["clock"]["simulation_timeouts"], 0);
}

// The shipped profiles use only what ships: the hardware show under --simulate, with no shared
// corpus anywhere, says nothing of one (its ps4 profile named a corpus descriptor, and warned).
TEST(RunSimulate, TheHardwareShowNeedsNoCorpus) {
  const auto r = test::run_cli("run '" + (test::source_dir() / kHardwareShow).string() + "' --headless --simulate --frames 30",
                               "MARIONETTE_CORPUS_DIR=/nonexistent");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("corpus"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
}

// The same show on a loaded machine (more busy threads than cores) gives what it gives on an
// idle one, frame for frame: one run_hash, every record, every detent and grab.
TEST(RunSimulate, HardwareShowGivesOneRunHashIdleAndLoaded) {
  const auto idle = run_hardware_show("idle");
  ASSERT_TRUE(idle.contains("run_hash"));
  test::CpuHog hog;
  for (int k = 0; k < test::repeats(5); ++k) {
    const auto j = run_hardware_show("loaded" + std::to_string(k));
    ASSERT_TRUE(j.contains("run_hash"));
    EXPECT_EQ(j["run_hash"], idle["run_hash"]) << "run " << k << " with " << hog.threads() << " busy threads";
    for (size_t i = 0; i < 4; ++i) {
      EXPECT_EQ(j["devices"][i]["records"], idle["devices"][i]["records"]) << "run " << k << ", device " << i;
      EXPECT_EQ(j["devices"][i]["events"], idle["devices"][i]["events"]) << "run " << k << ", device " << i;
    }
    EXPECT_EQ(j["devices"][2]["events"], 40);
    EXPECT_EQ(j["grabs"]["count"], 2);
    EXPECT_EQ(j["iterations"]["governor_reductions"], 0);
  }
}

// What a recording holds: wire records per source and kind, and device descriptions.
struct RecordingContents {
  std::map<std::pair<int, int>, int> wires;  ///< (source, kind) -> count
  std::map<int, int> descriptions;           ///< source -> connections described
  int frames = 0;
  bool ok = false;
};
RecordingContents read_recording(const std::filesystem::path& path) {
  RecordingContents c;
  auto p = Playback::open(path.string());
  if (!p.ok()) return c;
  std::vector<WireRecord> wires;
  int64_t t = 0;
  int it = 0;
  while ((*p.value)->next_frame(wires, t, it, [&](uint16_t src, std::span<const uint8_t>) { ++c.descriptions[src]; })) {
    ++c.frames;
    for (const WireRecord& r : wires) ++c.wires[{r.source, int(r.kind)}];
  }
  c.ok = (*p.value)->damage().empty();
  return c;
}

// A hardware show run on the bench and recorded replays to the same run_hash: the recording
// holds every device's wire bytes (USB-MIDI packets, HID reports, GPIO edges, evdev events)
// and each connection's description, and the replay decodes them again.
TEST(RunSimulate, RecordedHardwareShowReplaysToTheSameHash) {
  const auto dir = test::temp_dir("simulate-replay");
  const std::string show = (test::source_dir() / "config/shows/hardware.toml").string();
  const auto rec = dir / "hw.rec";
  const auto live = test::run_cli("run '" + show + "' --headless --simulate --record '" + rec.string() + "' --stats '" +
                                  (dir / "live.json").string() + "'");
  ASSERT_EQ(live.exit_code, 0) << live.err;
  const auto rep = test::run_cli("replay '" + rec.string() + "' --show '" + show + "' --stats '" + (dir / "replay.json").string() + "'");
  ASSERT_EQ(rep.exit_code, 0) << rep.err;
  std::ifstream a(dir / "live.json"), b(dir / "replay.json");
  const auto ja = nlohmann::json::parse(a), jb = nlohmann::json::parse(b);
  EXPECT_GT(ja["frames"].get<int>(), 100);
  EXPECT_EQ(ja["frames"], jb["frames"]);
  EXPECT_EQ(ja["run_hash"], jb["run_hash"]);
  const RecordingContents c = read_recording(rec);
  ASSERT_TRUE(c.ok);
  EXPECT_EQ(c.frames, ja["frames"].get<int>());
  const int kinds[] = {int(WireKind::UsbMidi), int(WireKind::HidReport), int(WireKind::GpioEdge), int(WireKind::EvdevEvent)};
  for (int src = 0; src < 4; ++src) {
    EXPECT_EQ(c.descriptions.count(src), 1u) << "device " << src << " has no description";
    EXPECT_GT((c.wires.count({src, kinds[src]}) ? c.wires.at({src, kinds[src]}) : 0), 0)
        << "device " << src << ": no " << wire_kind_name(WireKind(kinds[src])) << " records";
  }
  for (const auto& [key, n] : c.wires) EXPECT_NE(key.second, 5) << "decoded events in a recording";
  for (int src = 0; src < 4; ++src) EXPECT_EQ(jb["devices"][src]["events"], ja["devices"][src]["events"]) << src;
}

// The lights reach a controller through libusb as USB-MIDI packets (a SysEx in several): the
// emulated APC mini mk2, BeatStep and nanoKONTROL2 show what the show's state lit, as their
// in-process simulators do; the nanoKONTROL2 answers the scene requests that set its LED mode.
TEST(RunSimulate, LightsReachTheEmulatedControllersThroughLibusb) {
  const std::string rig = (test::source_dir() / "config/rigs/singer.toml").string();
  const std::string show = test::write_temp("leds_simulate.toml", "[show]\nrig = \"" + rig + R"("
rate = 60
[[device]]
name = "apc"
profile = "apc_mini_mk2"
script = """
0.2 press pad_r1c1
0.5 press pad_r2c1
"""
[[device]]
name = "steps"
profile = "beatstep"
script = "0.3 press pad1"
[[device]]
name = "korg"
profile = "nanokontrol2"
script = "0.4 press solo2"
[[binding]]
device = "korg"
control = "solo2"
target = "swap.eyes.eyes-shut"
[[binding]]
device = "apc"
control = "pad_r1c1"
target = "trigger.blush"
button = "toggle"
led = "pink"
[[binding]]
device = "apc"
control = "pad_r2c1"
target = "swap.mouth.mouth-a"
[[binding]]
device = "steps"
control = "pad1"
target = "trigger.blink"
button = "toggle"
)");
  const auto stats = test::temp_dir("simulate") / "leds.json";
  const auto r = test::run_cli("run '" + show + "' --headless --simulate --frames 60 --stats '" + stats.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(stats);
  const auto j = nlohmann::json::parse(in);
  ASSERT_TRUE(j.contains("leds")) << j.dump();
  EXPECT_EQ(j["leds"]["failed"], 0);
  const std::string apc = j["leds"]["simulators_show"].value("apc", ""), steps = j["leds"]["simulators_show"].value("steps", "");
  EXPECT_NE((" " + apc + " ").find(" pad_r1c1=57 "), std::string::npos) << apc;  // blush on: pink
  EXPECT_NE((" " + apc + " ").find(" pad_r2c1=21 "), std::string::npos) << apc;  // mouth-a shows: green
  EXPECT_NE((" " + steps + " ").find(" pad1=1 "), std::string::npos) << steps;   // blink on (a SysEx)
  EXPECT_EQ((" " + steps + " ").find(" pad2="), std::string::npos) << steps;     // unbound: never sent
  // The nanoKONTROL2 answered its scene requests through libusb and took the External LED mode.
  EXPECT_EQ(j["leds"]["korg_led_mode"], "switched");
  const std::string korg = j["leds"]["simulators_show"].value("korg", "");
  EXPECT_NE((" " + korg + " ").find(" solo2=127 "), std::string::npos) << korg;  // eyes shut (a swap stays)
}

}  // namespace
}  // namespace mar
