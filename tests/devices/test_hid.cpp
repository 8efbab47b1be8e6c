// HID over hidapi (hidraw): a simulated gamepad presented as /dev/hidraw0 with its report
// descriptor in sysfs; the real backend finds it by VID/PID, reads the descriptor from
// sysfs and decodes the reports; hotplug, garbage and permissions.
#include "bench_util.h"
#include "devices/backends.h"
#include "firmware_sim/hid_device.h"
#include "devices/vbench.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

std::unique_ptr<SimDevice> gamepad(const std::string& script) {
  auto d = make_sim_device("gamepad", "", 0, 1);
  EXPECT_TRUE(d.ok());
  EXPECT_TRUE((*d.value)->load_script(script).ok());
  return std::move(*d.value);
}

DeviceSpec pad_spec() {
  DeviceSpec s;
  s.name = "pad";
  s.type = "hid";
  s.vid = 0x054c;
  s.pid = 0x09cc;
  return s;
}

// The events the program's decoder makes of the simulator's reports, straight.
std::vector<Event> expected_events(SimDevice& sim, const HidDescriptor& d) {
  auto dec = make_hid_decoder(d, 0);
  std::vector<Event> out;
  sim.drain(INT64_MAX, [&](const WireRecord& r) { dec->feed(r, [&](const Event& e) { out.push_back(e); }); });
  sim.rewind();
  return out;
}

TEST(HidBackend, ScriptedStickAndButtonArriveAsTheDecodedEvents) {
  VirtualBench bench;
  auto sim = gamepad("0.05 stick left -1,-1 over 0.3\n0.4 press 2 for 0.1\n0.6 stick right 1,-0.5\n");
  auto& pad = static_cast<HidDeviceSim&>(*sim);
  const int dev = bench.add_hid({0x054c, 0x09cc, "Wireless Controller", "", pad.descriptor_bytes()});
  const auto want = expected_events(*sim, pad.descriptor());
  ASSERT_GT(want.size(), 20u);

  const int64_t epoch = monotonic_ns();
  DeviceSet set(epoch);
  set.add(make_hid_backend(pad_spec(), 0));
  set.start();
  ASSERT_EQ(set.state(0), DeviceState::Connected) << set.problem(0);
  EXPECT_EQ(set.backend(0).node(), "/dev/hidraw0");
  EXPECT_NE(set.backend(0).identity().find("054c:09cc"), std::string::npos);

  bench.play(dev, *sim, epoch);
  std::vector<Event> got;
  // The first report carries every field (nothing seen yet): compare from the last value.
  ASSERT_TRUE(test::poll_until(set, epoch, got, [&] { return bench.played_all() && got.size() >= want.size(); }))
      << got.size() << " of " << want.size() << " events, malformed " << set.status(0).malformed;
  ASSERT_EQ(got.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(got[i].kind, want[i].kind) << i;
    EXPECT_EQ(got[i].number, want[i].number) << i;
    EXPECT_EQ(got[i].value, want[i].value) << i;
    // hidraw carries no timestamps: events are stamped when read, after the report was sent.
    EXPECT_GE(got[i].t_ns, want[i].t_ns) << i;
    EXPECT_LT(got[i].t_ns, want[i].t_ns + 5'000'000'000) << i;  // and in this run
  }
  EXPECT_EQ(set.status(0).malformed, 0u);
}

TEST(HidBackend, MalformedReportsAreDroppedAndCounted) {
  VirtualBench bench;
  auto sim = gamepad("");
  auto& pad = static_cast<HidDeviceSim&>(*sim);
  const int dev = bench.add_hid({0x054c, 0x09cc, "Wireless Controller", "", pad.descriptor_bytes()});
  const int64_t epoch = monotonic_ns();
  DeviceSet set(epoch);
  set.add(make_hid_backend(pad_spec(), 0));
  set.start();
  ASSERT_EQ(set.state(0), DeviceState::Connected);
  // Reports shorter than the descriptor's (a garbled or truncated transfer). hidraw keeps
  // report boundaries: each is read before the next is written.
  const uint8_t too_short[] = {pad.descriptor().reports[0].id};
  const uint8_t also_short[] = {pad.descriptor().reports[0].id, 0x80};
  ASSERT_GT(pad.descriptor().reports[0].size_bytes(), 2u);
  std::vector<Event> got;
  bench.hid_report(dev, too_short);
  ASSERT_TRUE(test::poll_until(set, epoch, got, [&] { return set.status(0).malformed >= 1; }));
  bench.hid_report(dev, also_short);
  ASSERT_TRUE(test::poll_until(set, epoch, got, [&] { return set.status(0).malformed >= 2; }));
  EXPECT_EQ(set.status(0).malformed, 2u);
  EXPECT_TRUE(got.empty());
  EXPECT_EQ(set.state(0), DeviceState::Connected);  // garbage does not end the show
}

TEST(HidBackend, AbsentAtStartIsWaitedForThenConnects) {
  VirtualBench bench;
  const int64_t epoch = monotonic_ns();
  DeviceSet set(epoch);
  set.add(make_hid_backend(pad_spec(), 0));
  set.start(20);
  EXPECT_EQ(set.state(0), DeviceState::Waiting);
  EXPECT_NE(set.problem(0).find("054c:09cc"), std::string::npos) << set.problem(0);
  auto sim = gamepad("");
  bench.add_hid({0x054c, 0x09cc, "Wireless Controller", "", static_cast<HidDeviceSim&>(*sim).descriptor_bytes()});
  std::vector<Event> got;
  EXPECT_TRUE(test::poll_until(set, epoch, got, [&] { return set.state(0) == DeviceState::Connected; }, 2000));
}

TEST(HidBackend, PermissionDeniedNamesTheUdevRule) {
  VirtualBench bench;
  auto sim = gamepad("");
  const int dev = bench.add_hid({0x054c, 0x09cc, "Wireless Controller", "", static_cast<HidDeviceSim&>(*sim).descriptor_bytes()});
  bench.deny(dev, true);
  VirtualBench::act_as_user(true);
  DeviceSet set(monotonic_ns());
  set.add(make_hid_backend(pad_spec(), 0));
  set.start();
  VirtualBench::act_as_user(false);
  EXPECT_EQ(set.state(0), DeviceState::Denied);
  const std::string p = set.problem(0);
  EXPECT_NE(p.find("permission denied on /dev/hidraw0"), std::string::npos) << p;
  EXPECT_NE(p.find("config/udev/70-marionette.rules"), std::string::npos) << p;
  EXPECT_EQ(p.find('\n'), std::string::npos);  // one line
}

}  // namespace
}  // namespace mar
