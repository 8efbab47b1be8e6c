// A running show with one device of each hot-pluggable backend class — USB-MIDI (libusb), HID
// (hidapi on hidraw), GPIO (libgpiod) and a pen tablet (libevdev) — read from the virtual bench.
// The device is unplugged and replugged while frames run: each time it is seen unplugged and
// reconnected by identity within 1 s, and after the last replug its binding still moves the
// handle. 100 cycles a class here; MARIONETTE_HOTPLUG_CYCLES sets another count (the soak runs
// 1,000: `bash cmake/run.sh soak`).
#include "app/alloc_count.h"
#include "app/live.h"
#include "devices/bench_util.h"
#include "devices/vbench.h"
#include "firmware_sim/hid_device.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <linux/input.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <functional>

namespace mar {
namespace {

struct PlugClass {
  const char* name;
  std::string device;  ///< the show's [[device]] table
  std::string binding; ///< control (and what else the binding needs) moving hips.x over 100..200
  std::function<int(VirtualBench&)> add;
  /// Puts hips.x at 100 + 100 u through the device (u is 0.25 or 0.75).
  std::function<void(VirtualBench&, int dev, double u)> send;
};

std::vector<PlugClass> classes() {
  std::vector<PlugClass> out;
  out.push_back({"usb_midi", "type = \"usb_midi\"\nvid = 0x0944\npid = 0x0117\n",
                 "control = \"cc 0\"\ntarget = \"handle.hips.x\"\nrange = [100.0, 200.0]\ntakeover = false\n",
                 [](VirtualBench& b) { return b.add_usb_midi({}); },
                 [](VirtualBench& b, int dev, double u) {
                   const uint8_t cc[] = {0x0B, 0xB0, 0, uint8_t(std::lround(u * 127))};
                   b.usb_in(dev, cc);
                 }});
  out.push_back({"hid", "type = \"hid\"\nvid = 0x054c\npid = 0x09cc\n",
                 "control = \"usage x\"\ntarget = \"handle.hips.x\"\nrange = [100.0, 200.0]\ntakeover = false\n",
                 [](VirtualBench& b) {
                   auto sim = make_sim_device("gamepad", "", 0, 1);
                   auto& pad = static_cast<HidDeviceSim&>(**sim.value);
                   return b.add_hid({0x054c, 0x09cc, "Wireless Controller", "", pad.descriptor_bytes()});
                 },
                 [](VirtualBench& b, int dev, double u) {
                   auto sim = make_sim_device("gamepad", "", 0, 1);
                   auto& pad = static_cast<HidDeviceSim&>(**sim.value);
                   pad.set_unit(usage::X, u);
                   pad.send(0, usage::X);
                   WireRecord last;
                   for (const auto& r : pad.timeline()) last = r;
                   b.hid_report(dev, last.bytes());
                 }});
  // Two buttons recall two show poses that put the hips at x = 125 and x = 175.
  out.push_back({"gpio", "type = \"gpio\"\nchip = \"pinctrl-bcm2711\"\nbuttons = [\"SW1\", \"SW2\"]\ndebounce_ms = 1.0\n",
                 "control = \"button 1\"\ntarget = \"pose.low\"\ntransition = 0.0\n\n[[binding]]\ndevice = \"d\"\n"
                 "control = \"button 2\"\ntarget = \"pose.high\"\ntransition = 0.0\n",
                 [](VirtualBench& b) { return b.add_gpio({"pinctrl-bcm2711", {"SW1", "SW2"}}); },
                 [](VirtualBench& b, int dev, double u) {
                   const unsigned line = u < 0.5 ? 0 : 1;
                   b.gpio_edge(dev, line, 0, monotonic_ns());  // active low: pressed
                   std::this_thread::sleep_for(std::chrono::milliseconds(30));
                   b.gpio_edge(dev, line, 1, monotonic_ns());
                 }});
  out.push_back({"tablet", "type = \"tablet\"\nproduct = \"Pen\"\n",
                 "control = \"usage x\"\ntarget = \"handle.hips.x\"\nrange = [100.0, 200.0]\ntakeover = false\n",
                 [](VirtualBench& b) { return b.add_evdev({}); },
                 [](VirtualBench& b, int dev, double u) {
                   const int64_t t = monotonic_ns();
                   b.evdev_event(dev, EV_ABS, ABS_X, int32_t(std::lround(u * 21600)), t);
                   b.evdev_event(dev, EV_SYN, SYN_REPORT, 0, t);
                 }});
  return out;
}

int cycles() {
  const char* env = std::getenv("MARIONETTE_HOTPLUG_CYCLES");
  const int n = env ? std::atoi(env) : 100;
  return n > 0 ? n : 100;
}

void unplug_replug(const PlugClass& c) {
  VirtualBench bench;
  const int dev = c.add(bench);
  const std::string rig = (test::source_dir() / "config/rigs/figure.toml").string();
  const std::string show = test::write_temp(
      std::string("hotplug_") + c.name + ".toml",
      "[show]\nrig = \"" + rig + "\"\nrate = 60\n\n[[device]]\nname = \"d\"\n" + c.device +
          "\n[[pose]]\nname = \"low\"\nhandles = { hips = [125.0, 300.0] }\n\n[[pose]]\nname = \"high\"\n"
          "handles = { hips = [175.0, 300.0] }\n\n[[binding]]\ndevice = \"d\"\n" + c.binding);
  set_allocation_counter(&heap_allocation_count);  // this thread runs the frames
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  o.frames = 100'000'000;
  auto live = LiveShow::load(show, o);
  ASSERT_TRUE(live.ok()) << live.error;
  LiveShow& s = **live.value;
  ASSERT_NE(s.devices(), nullptr);
  ASSERT_EQ(s.devices()->state(0), DeviceState::Connected) << s.devices()->problem(0);

  const int n = cycles();
  std::vector<double> outage_ms;
  std::string failure;
  const double u = (n % 2) ? 0.25 : 0.75;
  std::thread plugger([&] {
    auto wait_for = [&](DeviceState st, int ms) {
      const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
      while (std::chrono::steady_clock::now() < end) {
        if (s.devices()->state(0) == st) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
      return false;
    };
    for (int k = 0; k < n && failure.empty(); ++k) {
      bench.unplug(dev);
      if (!wait_for(DeviceState::Unplugged, 1000)) failure = "unplug " + std::to_string(k) + " not seen";
      const auto t0 = std::chrono::steady_clock::now();
      bench.replug(dev);
      if (!wait_for(DeviceState::Connected, 1000)) failure = "replug " + std::to_string(k) + " not reconnected within 1 s";
      outage_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    c.send(bench, dev, u);  // after the last replug: does the binding still work?
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    s.stop();
  });
  EXPECT_EQ(s.run(), 0);
  plugger.join();
  ASSERT_TRUE(failure.empty()) << failure;
  ASSERT_EQ(outage_ms.size(), size_t(n));
  const auto st = s.devices()->status(0);
  EXPECT_EQ(st.unplugs, uint64_t(n));
  EXPECT_EQ(st.reconnects, uint64_t(n));
  double worst = 0;
  for (double ms : outage_ms) worst = std::max(worst, ms);
  EXPECT_LT(worst, 1000.0);
  // The binding survived: the last input put hips.x at 100 + 100 u.
  EXPECT_NEAR(s.mapping().targets()[size_t(s.mapping().handle_index("hips"))].x(), 100 + 100 * u, 1.0);
  const auto j = nlohmann::json::parse(s.stats_json());
  EXPECT_EQ(j["devices"][0]["status"], "connected");
  EXPECT_EQ(j["devices"][0]["unplugs"], n);
  // The loop ran on through every outage (frame timing is a measurement, not asserted here:
  // on the bench each read is a round trip to umockdev's thread).
  EXPECT_GT(int(j["frames"]), n);
  EXPECT_EQ(j["heap_allocations_after_warmup"], 0);
  std::printf("[ measure ] %s: %d replugs, worst reconnect %.1f ms, frames %d, overruns %d, frame p99 %.0f us\n", c.name, n,
              worst, int(j["frames"]), int(j["overruns"]), double(j["stages_us"]["frame"]["p99"]));
}

class LiveHotplug : public testing::TestWithParam<int> {};

TEST_P(LiveHotplug, UnplugReplugDuringAShow) { unplug_replug(classes()[size_t(GetParam())]); }

INSTANTIATE_TEST_SUITE_P(EveryClass, LiveHotplug, testing::Range(0, 4), [](const testing::TestParamInfo<int>& i) {
  return std::string(classes()[size_t(i.param)].name);
});

}  // namespace
}  // namespace mar
