// GPIO knobs over libgpiod, USB-MIDI over libusb and a pen tablet over libevdev, each
// against an emulated kernel device presenting a firmware_sim device.
#include "bench_util.h"
#include "devices/backends.h"
#include "firmware_sim/knob_box.h"
#include "firmware_sim/midi_controller.h"
#include "devices/vbench.h"

#include <gtest/gtest.h>
#include <libusb-1.0/libusb.h>
#include <poll.h>
#include <linux/gpio.h>
#include <linux/input.h>

#include <atomic>
#include <cstdio>
#include <thread>

namespace mar {
namespace {

DeviceSpec knob_spec() {
  DeviceSpec s;
  s.name = "knobs";
  s.type = "gpio";
  s.chip = "pinctrl-bcm2711";  // by label, as a Raspberry Pi 4 names its header chip
  for (int k = 1; k <= 4; ++k) {
    s.encoders.push_back({"ENC" + std::to_string(k) + "_A", "ENC" + std::to_string(k) + "_B", 4});
  }
  for (int k = 1; k <= 4; ++k) s.buttons.push_back("ENC" + std::to_string(k) + "_SW");
  return s;
}

// The knob box's lines (3(k-1) = A, +1 = B, +2 = switch) named as on the chip.
VirtualBench::Gpio knob_chip() {
  VirtualBench::Gpio g;
  for (int k = 1; k <= 4; ++k)
    for (const char* s : {"_A", "_B", "_SW"}) g.lines.push_back("ENC" + std::to_string(k) + s);
  return g;
}

// The bench writes the sim's edges on the chip line of the same name, stamped with the
// sim's times; frames run in virtual time (a frame at t reads every edge up to t), at a
// fast poll and at a 60 Hz show's rate, where one read holds a whole bounce burst.
class GpioFrames : public ::testing::TestWithParam<int64_t> {};

TEST_P(GpioFrames, BouncyEncoderTurnsAndPressArriveWithKernelTimestamps) {
  const int64_t period = GetParam();
  VirtualBench bench;
  const int chip = bench.add_gpio(knob_chip());
  KnobBoxSim sim(1.5, 7);  // 1.5 ms contact bounce
  ASSERT_TRUE(sim.load_script("0.05 turn 2 24 over 0.6\n0.8 turn 2 -5 over 0.2\n1.1 press 3 for 0.1\n").ok());
  const int64_t epoch = monotonic_ns();
  DeviceSpec spec = knob_spec();
  spec.debounce_ms = 2;
  DeviceSet set(epoch);
  set.add(make_gpio_backend(spec, 0));
  set.start();
  ASSERT_EQ(set.state(0), DeviceState::Connected) << set.problem(0);
  // Every line was requested for both edges with the pull-up bias.
  for (unsigned l = 0; l < 12; ++l) EXPECT_TRUE(bench.gpio_flags(chip, l) & GPIOHANDLE_REQUEST_BIAS_PULL_UP) << l;

  std::vector<std::pair<int64_t, int>> sim_edges;
  sim.drain(INT64_MAX, [&](const WireRecord& r) { sim_edges.push_back({r.t_ns, r.data[0]}); });
  ASSERT_GT(sim_edges.size(), 2u * (24 + 5) * 4);  // every quarter step, and bounces besides
  sim.rewind();
  std::vector<Event> got;
  test::poll_frames(set, 0, sim.end_ns() + 100'000'000, period, [&](int64_t now) {
    sim.drain(now, [&](const WireRecord& r) { bench.gpio_edge(chip, r.data[0], r.data[1], epoch + r.t_ns); });
  }, got);
  int net = 0, presses = 0, releases = 0;
  for (const Event& e : got) {
    if (e.kind == ControlKind::EncoderDelta && e.number == 2) net += e.value;
    if (e.kind == ControlKind::Button && e.number == 3) ++(e.value == 1 ? presses : releases);
  }
  EXPECT_EQ(net, 24 - 5);
  EXPECT_EQ(presses, 1);
  EXPECT_EQ(releases, 1);
  // Timestamps are the kernel's (the bench's) edge times: an event made by an edge has that
  // edge's exact time; one made when a debounced level settles is stamped at the frame that
  // saw it settle, at least the 2 ms debounce after the first edge of the gesture.
  int exact = 0;
  for (const Event& e : got) {
    bool at_edge = false;
    for (const auto& [t, line] : sim_edges) at_edge = at_edge || e.t_ns == t;
    exact += at_edge;
    EXPECT_TRUE(at_edge || e.t_ns >= sim_edges.front().first + 2'000'000) << "event at " << e.t_ns;
  }
  EXPECT_GT(exact, 0);
}

INSTANTIATE_TEST_SUITE_P(GpioBackend, GpioFrames, ::testing::Values(int64_t{1'000'000}, int64_t{16'666'667}),
                         [](const ::testing::TestParamInfo<int64_t>& p) { return p.param == 1'000'000 ? "every_ms" : "at_60Hz"; });

TEST(GpioBackend, UnplugHangsUpAndTheChipIsReopenedByLabelAndLineNames) {
  VirtualBench bench;
  const int chip = bench.add_gpio(knob_chip());
  const int64_t epoch = monotonic_ns();
  DeviceSet set(epoch);
  set.add(make_gpio_backend(knob_spec(), 0));
  set.start(20);
  ASSERT_EQ(set.state(0), DeviceState::Connected);
  std::vector<Event> got;
  bench.unplug(chip);
  ASSERT_TRUE(test::poll_until(set, epoch, got, [&] { return set.state(0) == DeviceState::Unplugged; }, 2000));
  bench.replug(chip);
  ASSERT_TRUE(test::poll_until(set, epoch, got, [&] { return set.state(0) == DeviceState::Connected; }, 1000));
  // Events flow again: one detent on encoder 1 (A then B fall, then rise).
  const int64_t t = monotonic_ns();
  bench.gpio_edge(chip, 0, 0, t);
  bench.gpio_edge(chip, 1, 0, t + 1000);
  bench.gpio_edge(chip, 0, 1, t + 2000);
  bench.gpio_edge(chip, 1, 1, t + 3000);
  ASSERT_TRUE(test::poll_until(set, epoch, got, [&] { return !got.empty(); }, 1000));
  EXPECT_EQ(got[0].kind, ControlKind::EncoderDelta);
  EXPECT_EQ(std::abs(got[0].value), 1);
  EXPECT_EQ(got[0].t_ns, t + 3000 - epoch);
  EXPECT_EQ(set.status(0).reconnects, 1u);
}

TEST(GpioBackend, MissingLineNameSaysWhich) {
  VirtualBench bench;
  VirtualBench::Gpio g = knob_chip();
  g.lines[4] = "OTHER";
  bench.add_gpio(g);
  DeviceSet set(monotonic_ns());
  set.add(make_gpio_backend(knob_spec(), 0));
  set.start();
  EXPECT_EQ(set.state(0), DeviceState::Waiting);
  EXPECT_NE(set.problem(0).find("'ENC2_B' not found"), std::string::npos) << set.problem(0);
}

DeviceSpec midi_spec() {
  DeviceSpec s;
  s.name = "nk2";
  s.type = "usb_midi";
  s.vid = 0x0944;
  s.pid = 0x0117;
  return s;
}

TEST(UsbMidiBackend, FaderAndButtonsArriveAndFeedbackGoesOut) {
  VirtualBench bench;
  const int dev = bench.add_usb_midi({0x0944, 0x0117, true});
  MidiControllerSim sim;
  ASSERT_TRUE(sim.load_script("0.02 move fader1 0\n0.05 move fader1 1 over 0.3\n0.4 press solo2 for 0.05\n").ok());
  std::vector<Event> want;
  {
    auto dec = make_midi_decoder(WireKind::UsbMidi, 0);
    sim.drain(INT64_MAX, [&](const WireRecord& r) { dec->feed(r, [&](const Event& e) { want.push_back(e); }); });
    sim.rewind();
  }
  const int64_t epoch = monotonic_ns();
  DeviceSet set(epoch);
  set.add(make_usb_midi_backend(midi_spec(), 0));
  set.start();
  ASSERT_EQ(set.state(0), DeviceState::Connected) << set.problem(0);
  EXPECT_TRUE(bench.kernel_driver_detached(dev));  // snd-usb-audio let go of the interface
  EXPECT_EQ(set.backend(0).node(), "/dev/bus/usb/001/002");
  bench.play(dev, sim, epoch);
  std::vector<Event> got;
  ASSERT_TRUE(test::poll_until(set, epoch, got, [&] { return bench.played_all() && got.size() >= want.size(); }));
  ASSERT_EQ(got.size(), want.size());
  for (size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(got[i].kind, want[i].kind);
    EXPECT_EQ(got[i].number, want[i].number);
    EXPECT_EQ(got[i].value, want[i].value);
    EXPECT_GE(got[i].t_ns, want[i].t_ns);  // stamped when the transfer completed
  }
  // Feedback: light solo2's LED (CC 33 = 127 on channel 1) with a bulk OUT packet.
  const uint8_t cc[3] = {0xB0, 33, 127};
  ASSERT_TRUE(set.backend(0).send_midi(cc));
  ASSERT_TRUE(test::poll_until(set, epoch, got, [&] { return bench.usb_out(dev).size() >= 4; }, 1000));
  EXPECT_EQ(bench.usb_out(dev), (std::vector<uint8_t>{0x0B, 0xB0, 33, 127}));
}

TEST(UsbMidiBackend, GarbageBytesAreCountedAndUnplugIsSeen) {
  VirtualBench bench;
  const int dev = bench.add_usb_midi({});
  const int64_t epoch = monotonic_ns();
  DeviceSet set(epoch);
  set.add(make_usb_midi_backend(midi_spec(), 0));
  set.start(20);
  ASSERT_EQ(set.state(0), DeviceState::Connected);
  // (Waits are generous: they end as soon as the condition holds, and a busy machine is slow.)
  const uint8_t garbage[] = {0x0B, 0xB0, 7, 100, 0xFF, 0x13};  // a packet and 2 stray bytes
  bench.usb_in(dev, garbage);
  std::vector<Event> got;
  ASSERT_TRUE(test::poll_until(set, epoch, got, [&] { return !got.empty() && set.status(0).malformed > 0; }, 10000));
  EXPECT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].number, 7u);
  bench.unplug(dev);
  ASSERT_TRUE(test::poll_until(set, epoch, got, [&] { return set.state(0) == DeviceState::Unplugged; }, 10000));
  bench.replug(dev);
  ASSERT_TRUE(test::poll_until(set, epoch, got, [&] { return set.state(0) == DeviceState::Connected; }, 10000));
  const uint8_t cc[] = {0x0B, 0xB0, 8, 1};
  bench.usb_in(dev, cc);
  ASSERT_TRUE(test::poll_until(set, epoch, got, [&] { return got.size() == 2; }, 10000));
  EXPECT_EQ(got[1].number, 8u);
}

// Just after an unplug the device's entry may still be listed with its node gone: the next
// controller with the same IDs is opened instead (and an open descriptor of the gone one gets
// ENODEV, never a wait: the bench answers it as the kernel does).
TEST(UsbMidiBackend, AListedDeviceThatCannotBeOpenedDoesNotHideTheNext) {
  for (int gone : {0, 1}) {  // whichever of the two is listed first
    VirtualBench bench;
    bench.add_usb_midi({0x0944, 0x0117, false});
    bench.add_usb_midi({0x0944, 0x0117, false});
    bench.unplug(gone);
    DeviceSet set(monotonic_ns());
    set.add(make_usb_midi_backend(midi_spec(), 0));
    set.start();
    ASSERT_EQ(set.state(0), DeviceState::Connected) << set.problem(0);
    EXPECT_EQ(set.backend(0).node(), gone == 0 ? "/dev/bus/usb/001/003" : "/dev/bus/usb/001/002");
  }
}

// The bench as the kernel: URBs belong to the descriptor that submitted them, and closing it
// discards them. A handle closed after an unplug without reaping its transfers (as a close
// that gives up waiting does) left them queued on the device, and the next plug's first reap
// was answered with one of them: umockdev then wrote it back through the closed descriptor's
// stream, failed, and never answered — the USB-MIDI hot-plug hang seen under ASan in CI.
TEST(UsbMidiBench, UrbsOfAClosedHandleAreNeverReapedByTheNextPlug) {
  VirtualBench bench;
  const int dev = bench.add_usb_midi({});
  libusb_context* ctx = nullptr;
  ASSERT_EQ(libusb_init(&ctx), 0);
  auto open_first = [&] {
    libusb_device** list = nullptr;
    libusb_device_handle* h = nullptr;
    const ssize_t n = libusb_get_device_list(ctx, &list);
    for (ssize_t i = 0; i < n && !h; ++i)
      if (libusb_open(list[i], &h) != 0) h = nullptr;
    if (n >= 0) libusb_free_device_list(list, 1);
    if (h && libusb_claim_interface(h, 1) != 0) {
      libusb_close(h);
      h = nullptr;
    }
    return h;
  };
  struct In {
    uint8_t buf[64];
    int done = 0, length = 0;
    libusb_transfer_status status = LIBUSB_TRANSFER_ERROR;
  };
  auto submit = [](libusb_device_handle* h, In& in) {
    libusb_transfer* t = libusb_alloc_transfer(0);
    libusb_fill_bulk_transfer(t, h, 0x81, in.buf, sizeof in.buf,
                              [](libusb_transfer* x) {
                                auto* p = static_cast<In*>(x->user_data);
                                p->status = x->status;
                                p->length = x->actual_length;
                                ++p->done;
                              },
                              &in, 0);
    EXPECT_EQ(libusb_submit_transfer(t), 0);
    return t;
  };
  libusb_device_handle* old = open_first();
  ASSERT_NE(old, nullptr);
  In stale[4];
  libusb_transfer* ts[4];
  for (int i = 0; i < 4; ++i) ts[i] = submit(old, stale[i]);
  bench.unplug(dev);
  for (auto* t : ts) libusb_cancel_transfer(t);
  libusb_release_interface(old, 1);
  libusb_close(old);  // nothing reaped: the four URBs are still the old descriptor's
  for (auto* t : ts) libusb_free_transfer(t);

  bench.replug(dev);
  libusb_device_handle* h = open_first();
  ASSERT_NE(h, nullptr);
  In fresh;
  libusb_transfer* t = submit(h, fresh);
  const uint8_t cc[] = {0x0B, 0xB0, 9, 42};
  bench.usb_in(dev, cc);
  // Before the fix the first reap below never returned: it runs on its own thread so that the
  // test can fail with a message instead of hanging.
  std::atomic<bool> finished{false};
  std::thread events([&] {
    timeval tv{0, 10000};
    for (int k = 0; k < 1000 && !fresh.done; ++k) libusb_handle_events_timeout_completed(ctx, &tv, nullptr);
    finished = true;
  });
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (!finished && std::chrono::steady_clock::now() < end) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  if (!finished) {
    ADD_FAILURE() << "a reap on the replugged device never returned";
    std::fflush(nullptr);
    std::_Exit(1);
  }
  events.join();
  EXPECT_EQ(fresh.done, 1);
  EXPECT_EQ(fresh.status, LIBUSB_TRANSFER_COMPLETED);
  ASSERT_EQ(fresh.length, 4);
  EXPECT_EQ(std::vector<uint8_t>(fresh.buf, fresh.buf + 4), std::vector<uint8_t>(cc, cc + 4));
  for (const In& s : stale) EXPECT_EQ(s.done, 0);  // the old handle's callbacks never ran
  libusb_release_interface(h, 1);
  libusb_close(h);
  libusb_free_transfer(t);
  libusb_exit(ctx);
}

TEST(TabletBackend, PenStrokeWithPressureAndTiltKeepsTheKernelTimestamps) {
  VirtualBench bench;
  VirtualBench::Evdev pen;
  pen.name = "Wacom Intuos S Pen";
  const int dev = bench.add_evdev(pen);
  const int64_t epoch = monotonic_ns();
  DeviceSpec s;
  s.name = "pen";
  s.type = "tablet";
  s.product = "Intuos";
  DeviceSet set(epoch);
  set.add(make_tablet_backend(s, 0));
  set.start();
  ASSERT_EQ(set.state(0), DeviceState::Connected) << set.problem(0);
  EXPECT_NE(set.backend(0).identity().find("Wacom Intuos S Pen"), std::string::npos);
  const int64_t t0 = monotonic_ns();
  bench.evdev_event(dev, EV_KEY, BTN_TOOL_PEN, 1, t0);
  bench.evdev_event(dev, EV_ABS, ABS_X, 10800, t0);
  bench.evdev_event(dev, EV_ABS, ABS_Y, 6750, t0);
  bench.evdev_event(dev, EV_SYN, SYN_REPORT, 0, t0);
  bench.evdev_event(dev, EV_KEY, BTN_TOUCH, 1, t0 + 5'000'000);
  bench.evdev_event(dev, EV_ABS, ABS_PRESSURE, 512, t0 + 5'000'000);
  bench.evdev_event(dev, EV_ABS, ABS_TILT_X, -20, t0 + 5'000'000);
  bench.evdev_event(dev, EV_SYN, SYN_REPORT, 0, t0 + 5'000'000);
  // The device's fd says there is input (a loop may wait on it; the frame never does).
  const auto fds = set.backend(0).pollable_fds();
  ASSERT_EQ(fds.size(), 1u);
  pollfd pf{fds[0], POLLIN, 0};
  EXPECT_EQ(::poll(&pf, 1, 10000), 1);
  std::vector<Event> got;
  ASSERT_TRUE(test::poll_until(set, epoch, got, [&] { return got.size() >= 6; }, 2000));
  ASSERT_EQ(got.size(), 6u);
  const uint32_t usage[6] = {0x0D0032, 0x010030, 0x010031, 0x0D0042, 0x0D0030, 0x0D003D};
  const int32_t value[6] = {1, 10800, 6750, 1, 512, -20};
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(got[size_t(i)].number, usage[i]) << i;
    EXPECT_EQ(got[size_t(i)].value, value[i]) << i;
    EXPECT_EQ(got[size_t(i)].t_ns, (i < 3 ? t0 : t0 + 5'000'000) / 1000 * 1000 - epoch) << i;  // µs resolution
  }
  EXPECT_EQ(got[1].hi, 21600);
  EXPECT_EQ(got[4].hi, 1023);
  EXPECT_EQ(got[5].lo, -64);
}

}  // namespace
}  // namespace mar
