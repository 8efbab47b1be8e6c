// Simulated devices: their wire output decodes, through the program's decoders, to the
// gestures that produced it; layouts follow the real devices in the corpus.
#include "firmware_sim/hid_device.h"
#include "firmware_sim/knob_box.h"
#include "firmware_sim/midi_controller.h"
#include "input/quadrature.h"
#include "input/usb_midi.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

namespace mar {
namespace {

TEST(MidiControllerSim, CcNumbersMatchArdoursNanoKontrol2Map) {
  const auto p = test::corpus_dir() / "midi/ardour-midi-maps/Korg_nanoKONTROL2.map";
  if (!std::filesystem::exists(p)) GTEST_SKIP() << "corpus not found";
  std::ifstream in(p);
  // Binding lines: <Binding channel="1" ctl="N" uri="/route/WHAT BK"/> or function="transport-...".
  auto attr = [](const std::string& line, const std::string& key) {
    const auto at = line.find(key + "=\"");
    if (at == std::string::npos) return std::string();
    const auto start = at + key.size() + 2;
    return line.substr(start, line.find('"', start) - start);
  };
  int checked = 0, transport = 0;
  for (std::string line; std::getline(in, line);) {
    const std::string ctl = attr(line, "ctl"), uri = attr(line, "uri"), fn = attr(line, "function");
    if (ctl.empty()) continue;
    const int cc = std::stoi(ctl);
    if (uri.rfind("/route/", 0) == 0) {
      const std::string what = uri.substr(7, uri.find(' ') - 7), bank = uri.substr(uri.find(" B") + 2);
      const std::string name = what == "gain" ? "fader" : what == "pandirection" ? "knob" : what == "recenable" ? "rec" : what;
      EXPECT_EQ(MidiControllerSim::cc_of(name + bank), cc) << name << bank;
      ++checked;
    } else if (fn == "transport-roll" || fn == "transport-stop") {
      EXPECT_EQ(MidiControllerSim::cc_of(fn == "transport-roll" ? "play" : "stop"), cc);
      ++transport;
    }
  }
  EXPECT_EQ(checked, 40);
  EXPECT_EQ(transport, 2);
}

TEST(MidiControllerSim, FaderSweepDecodesTo127IncreasingCCs) {
  MidiControllerSim sim;
  ASSERT_TRUE(sim.load_script("0 move fader3 0\n0.5 move fader3 1 over 1.0\n").ok());
  UsbMidiDecoder dec;
  std::vector<std::pair<int64_t, int>> values;
  sim.drain(INT64_MAX, [&](const WireRecord& r) {
    EXPECT_EQ(r.kind, WireKind::UsbMidi);
    dec.feed(r.bytes(), [&](uint8_t, const MidiMessage& m) {
      EXPECT_EQ(m.bytes[0], 0xB0);
      EXPECT_EQ(m.bytes[1], 2);
      values.push_back({r.t_ns, m.bytes[2]});
    });
  });
  ASSERT_EQ(values.size(), 128u);  // the initial 0, then 1..127
  for (size_t i = 1; i < values.size(); ++i) {
    EXPECT_EQ(values[i].second, int(i));
    EXPECT_GE(values[i].first, values[i - 1].first);
  }
  EXPECT_NEAR(double(values.back().first) * 1e-9, 1.5, 5e-3);  // 127 reached in the last 1/254 s
}

// The CCs a move sends, as (time, value): what the firmware's 1 kHz ADC scan sends, one
// scan at a time (the reference the simulator's jump from change to change must match).
std::vector<std::pair<int64_t, int>> scanned_move(double t_s, int from, int target, double dur_s) {
  std::vector<std::pair<int64_t, int>> out;
  const int steps = int(std::ceil(dur_s * 1000));
  int last = from;
  for (int k = 1; k <= steps; ++k) {
    const double u = double(k) / steps;
    const int v = int(std::lround(from + (target - from) * u));
    if (v != last) out.push_back({to_ns(t_s + u * dur_s), last = v});
  }
  return out;
}

std::vector<std::pair<int64_t, int>> sent_ccs(MidiControllerSim& sim, int64_t after_ns) {
  std::vector<std::pair<int64_t, int>> out;
  UsbMidiDecoder dec;
  sim.drain(INT64_MAX, [&](const WireRecord& r) {
    dec.feed(r.bytes(), [&](uint8_t, const MidiMessage& m) {
      if (r.t_ns > after_ns) out.push_back({r.t_ns, m.bytes[2]});
    });
  });
  return out;
}

TEST(MidiControllerSim, MovesSendWhatTheFirmwaresScanSends) {
  for (double from : {0.0, 0.3, 1.0})
    for (double to : {0.0, 0.55, 1.0})
      for (double dur : {0.001, 0.004, 0.05, 0.127, 0.3, 1.0, 2.7, 600.0}) {
        MidiControllerSim sim;
        std::ostringstream script;
        script << "0 move knob1 " << from << "\n0.25 move knob1 " << to << " over " << dur << "\n";
        ASSERT_TRUE(sim.load_script(script.str()).ok()) << script.str();
        const int a = int(std::lround(from * 127)), b = int(std::lround(to * 127));
        EXPECT_EQ(sent_ccs(sim, 0), scanned_move(0.25, a, b, dur)) << script.str();
      }
}

// A fader moved over a day (the longest a script allows) sends its 127 CCs at once; the
// scan would have taken 10^8 steps to load (found by fuzz_show_toml: seconds per load).
TEST(MidiControllerSim, AMoveOverADayIs127CCs) {
  MidiControllerSim sim;
  ASSERT_TRUE(sim.load_script("0.5 move knob1 1.0 over 1E5\n").ok());
  const auto ccs = sent_ccs(sim, -1);
  ASSERT_EQ(ccs.size(), 127u);
  for (size_t i = 0; i < ccs.size(); ++i) {
    EXPECT_EQ(ccs[i].second, int(i) + 1);
    // Value v is first sent at the scan where v - 1/2 of the 127 steps has passed.
    const double expect = 0.5 + 1e5 * (double(i) + 0.5) / 127;
    EXPECT_NEAR(double(ccs[i].first) * 1e-9, expect, 2e-3) << i;  // the next 1 ms scan
  }
}

TEST(MidiControllerSim, ScriptErrorsNameTheLine) {
  MidiControllerSim sim;
  auto r = sim.load_script("0 move fader1 0.5\n1.0 move fader9 1\n");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("line 2"), std::string::npos) << r.error;
  EXPECT_TRUE(sim.timeline().empty());
  EXPECT_FALSE(sim.load_script("x move fader1 1").ok());
  EXPECT_FALSE(sim.load_script("0 wiggle fader1").ok());
}

// A script's limits: times and durations past 100,000 s, more than 250,000 records, and a loop
// shorter than the script or than 10 ms are errors naming the line; nothing of it is kept.
TEST(SimDevice, ScriptLimitsAreErrorsWithTheLine) {
  MidiControllerSim m;
  auto r = m.load_script("0 move fader1 0\n1e300 move fader1 1\n");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("line 2: a time or duration past 100000 s"), std::string::npos) << r.error;
  r = m.load_script("0 move fader1 1 over 1e9\n");
  EXPECT_NE(r.error.find("line 1: a time or duration past"), std::string::npos) << r.error;
  r = m.load_script("0 press play\nloop 0.001\n");
  EXPECT_NE(r.error.find("line 2: expected 'loop SECONDS' with SECONDS >= 0.01"), std::string::npos) << r.error;
  r = m.load_script("0 press play\n3 press stop\nloop 1\n");
  EXPECT_NE(r.error.find("the period is shorter than the script"), std::string::npos) << r.error;
  EXPECT_TRUE(m.timeline().empty());
  KnobBoxSim k;
  r = k.load_script("0 turn 1 1000000 over 10\n");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("more than 250000 records"), std::string::npos) << r.error;
  EXPECT_TRUE(k.timeline().empty());
  // A loop far behind (a show stalled for an hour) replays at most 64 periods at once.
  ASSERT_TRUE(m.load_script("0 press play for 0.001\nloop 0.01\n").ok());
  int n = 0;
  m.drain(to_ns(3600), [&](const WireRecord&) { ++n; });
  EXPECT_LE(n, 2 * 67);
  EXPECT_GE(n, 2 * 64);
}

// A lowered record limit (the fuzz harness's) refuses past it with the same message, and a
// script within it loads whole.
TEST(SimDevice, ALoweredRecordLimitIsTheLimit) {
  KnobBoxSim k;
  k.set_max_records(1000);
  auto r = k.load_script("0 turn 1 1000 over 10\n");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("line 1: the script makes more than 1000 records"), std::string::npos) << r.error;
  EXPECT_TRUE(k.timeline().empty());
  ASSERT_TRUE(k.load_script("0 turn 1 100 over 1\n").ok());
  EXPECT_GT(k.timeline().size(), 100u);
  EXPECT_LE(k.timeline().size(), 1000u);
  k.set_max_records(SimDevice::kMaxRecords + 1);  // never above the program's own limit
  r = k.load_script("0 turn 1 1000000 over 10\n");
  EXPECT_NE(r.error.find("more than 250000 records"), std::string::npos) << r.error;
}

TEST(KnobBoxSim, TwentyFourDetentsWithBounceDecodeExactly) {
  for (double bounce : {0.0, 1.0, 5.0}) {
    KnobBoxSim sim(bounce, 42);
    ASSERT_TRUE(sim.load_script("0 turn 2 24 over 2.0\n3 turn 2 -5 over 0.5\n4 press 2 for 0.2\n").ok());
    QuadratureDecoder q(4);
    q.set_levels(true, true);
    int presses = 0, button = 1, edges = 0;
    int64_t last_button = -1'000'000'000;
    std::vector<int> detents;
    sim.drain(INT64_MAX, [&](const WireRecord& r) {
      const int line = r.data[0], level = r.data[1];
      ++edges;
      if (line == KnobBoxSim::line_button(2)) {
        // lockout debounce: the first edge counts, chatter within 10 ms is ignored
        if (level != button && r.t_ns - last_button > 10'000'000) {
          button = level;
          last_button = r.t_ns;
          presses += level == 0;
        }
        return;
      }
      ASSERT_TRUE(line == KnobBoxSim::line_a(2) || line == KnobBoxSim::line_b(2));
      if (r.t_ns > 2'900'000'000 && detents.size() == 0) detents.push_back(q.take_detents());
      q.edge({r.t_ns, uint8_t(line == KnobBoxSim::line_a(2) ? 0 : 1), uint8_t(level)});
    });
    detents.push_back(q.take_detents());
    ASSERT_EQ(detents.size(), 2u);
    EXPECT_EQ(detents[0], 24) << "bounce " << bounce;
    EXPECT_EQ(detents[1], -5) << "bounce " << bounce;
    EXPECT_EQ(presses, 1);
    if (bounce > 0) {
      EXPECT_GT(edges, 4 * 29 + 2) << "bounce adds edges";
    } else {
      EXPECT_EQ(edges, 4 * 29 + 2);
    }
  }
}

// Decodes the reports of a pen simulator back into (x, y, pressure, tip).
struct PenSample {
  double x, y, p;
  int tip;
};
std::vector<PenSample> decode_pen(const PenTabletSim& sim, SimDevice& dev) {
  const HidDescriptor& d = sim.descriptor();
  std::vector<PenSample> out;
  dev.drain(INT64_MAX, [&](const WireRecord& r) {
    const HidReport* rep = d.input_for(r.bytes());
    EXPECT_NE(rep, nullptr);
    if (!rep) return;
    EXPECT_EQ(r.size, rep->size_bytes());
    auto get = [&](uint32_t u) {
      int k = 0;
      const HidField* f = d.find_usage(u, &k);
      int32_t v = 0;
      EXPECT_TRUE(f && f->value(r.bytes(), k, v));
      return f ? double(v - f->logical_min) / (f->logical_max - f->logical_min) : 0.0;
    };
    out.push_back({get(usage::X), get(usage::Y), get(usage::TipPressure), int(get(usage::TipSwitch))});
  });
  return out;
}

TEST(PenTabletSim, RealDescriptorsCarryTheStroke) {
  const auto root = test::corpus_dir() / "hid";
  if (!std::filesystem::exists(root)) GTEST_SKIP() << "corpus not found";
  for (const char* file : {"wacom-hid-descriptors/Huion_H640P/0003_256C_006D.0006.hid.bin",
                           "hid-tools-descriptors/test_tablet__TestXPPen_Artist24_28bd_093a.hex",
                           "wacom-hid-descriptors/Huion_H640P/0003_256C_006D.0005.hid.bin", ""}) {
    SCOPED_TRACE(file);
    auto dev = make_sim_device("pen_tablet", *file ? (root / file).string() : "");
    ASSERT_TRUE(dev.ok()) << dev.error;
    auto* pen = static_cast<PenTabletSim*>(dev.value->get());
    ASSERT_TRUE(pen->load_script("0 stroke 0.1,0.2 0.9,0.2 over 1.0 pressure 0.6\n").ok());
    const auto s = decode_pen(*pen, *pen);
    ASSERT_EQ(s.size(), 202u);  // 200 Hz over 1 s, both ends, and the lift
    EXPECT_NEAR(s.front().x, 0.1, 1e-3);
    EXPECT_NEAR(s[100].x, 0.5, 1e-3);
    EXPECT_NEAR(s[200].x, 0.9, 1e-3);
    EXPECT_NEAR(s[100].y, 0.2, 1e-3);
    EXPECT_NEAR(s[100].p, 0.6, 1e-3);
    EXPECT_EQ(s[100].tip, 1);
    EXPECT_EQ(s.back().tip, 0);
  }
}

TEST(GamepadSim, Ps4UsbReportsCarrySticksAndButtons) {
  const auto p = test::corpus_dir() / "hid/hid-tools-descriptors/sony_gamepad__PS4ControllerUSB.hex";
  if (!std::filesystem::exists(p)) GTEST_SKIP() << "corpus not found";
  auto dev = make_sim_device("gamepad", p.string());
  ASSERT_TRUE(dev.ok()) << dev.error;
  auto* pad = static_cast<GamepadSim*>(dev.value->get());
  ASSERT_TRUE(pad->load_script("0 stick left 1,-1 over 0.1\n0.2 press 2 for 0.1\n").ok());
  const HidDescriptor& d = pad->descriptor();
  std::vector<std::array<int32_t, 4>> got;  // X, Y, B2, hat
  pad->drain(INT64_MAX, [&](const WireRecord& r) {
    ASSERT_EQ(r.size, 64);
    ASSERT_EQ(r.data[0], 1);  // report ID 1
    std::array<int32_t, 4> v{};
    const uint32_t us[4] = {usage::X, usage::Y, usage::button(2), usage::Hat};
    for (int i = 0; i < 4; ++i) {
      int k = 0;
      const HidField* f = d.find_usage(us[i], &k);
      ASSERT_NE(f, nullptr);
      ASSERT_TRUE(f->value(r.bytes(), k, v[size_t(i)]));
    }
    got.push_back(v);
  });
  ASSERT_EQ(got.size(), 25u + 2u);
  EXPECT_EQ(got[24][0], 255);
  EXPECT_EQ(got[24][1], 0);
  EXPECT_EQ(got[25][2], 1);
  EXPECT_EQ(got[26][2], 0);
  EXPECT_EQ(got[0][3], 8);  // hat at rest: null state
}

TEST(SimDevice, LoopRepeatsTheTimeline) {
  MidiControllerSim sim;
  ASSERT_TRUE(sim.load_script("0.1 press play for 0.1\nloop 1.0\n").ok());
  int n = 0;
  int64_t last = 0;
  sim.drain(to_ns(3.5), [&](const WireRecord& r) {
    ++n;
    last = r.t_ns;
  });
  EXPECT_EQ(n, 8);  // 4 cycles (0, 1, 2, 3 s) x press and release
  EXPECT_EQ(last, to_ns(3.2));
}

}  // namespace
}  // namespace mar
