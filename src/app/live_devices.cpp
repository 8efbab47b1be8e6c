// The live show's hardware devices: backends in a DeviceSet, and for --simulate the show's
// simulators presented at the kernel interface on the virtual bench.
#include "app/live.h"
#include "devices/backends.h"
#include "firmware_sim/hid_device.h"
#include "input/hid_usages.h"

#include <linux/input.h>

#include <atomic>
#include <csignal>
#include <iostream>

namespace mar {
namespace {

std::atomic<bool> g_quit{false};
void on_signal(int) { g_quit = true; }

// A pen simulator's HID reports as evdev events (the bench's evdev node).
void present_pen_as_evdev(VirtualBench& bench, int dev, const WireRecord& r, int64_t epoch, WireDecoder& dec,
                          const VirtualBench::Evdev& geom) {
  dec.feed(r, [&](const Event& e) {
    if (e.kind != ControlKind::HidValue) return;
    const double u = e.hi > e.lo ? double(e.value - e.lo) / (e.hi - e.lo) : 0;
    const int64_t t = epoch + r.t_ns;
    switch (e.number) {
      case usage::kX: bench.evdev_event(dev, EV_ABS, ABS_X, int32_t(u * geom.x_max), t); break;
      case usage::kY: bench.evdev_event(dev, EV_ABS, ABS_Y, int32_t(u * geom.y_max), t); break;
      case usage::kTipPressure: bench.evdev_event(dev, EV_ABS, ABS_PRESSURE, int32_t(u * geom.pressure_max), t); break;
      case usage::kTipSwitch: bench.evdev_event(dev, EV_KEY, BTN_TOUCH, e.value, t); break;
      case usage::kInRange: bench.evdev_event(dev, EV_KEY, BTN_TOOL_PEN, e.value, t); break;
      case usage::kBarrelSwitch: bench.evdev_event(dev, EV_KEY, BTN_STYLUS, e.value, t); break;
      default: return;
    }
    bench.evdev_event(dev, EV_SYN, SYN_REPORT, 0, t);
  });
}

}  // namespace

void install_quit_handler() {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
}
bool quit_requested() { return g_quit.load(); }

std::string LiveShow::open_hardware() {
  std::vector<size_t> hw;
  for (size_t i = 0; i < show_.devices.size(); ++i)
    if (show_.devices[i].type != "sim") hw.push_back(i);
  if (hw.empty()) return {};
  epoch_ns_ = monotonic_ns();
  std::vector<int> bench_dev(show_.devices.size(), -1);
  if (opt_.simulate) {
    if (!VirtualBench::preload_active()) return "--simulate needs umockdev's preload (marionette re-executes itself with it)";
    bench_ = std::make_unique<VirtualBench>();
    for (size_t i : hw) {
      ShowDevice& d = show_.devices[i];
      SimDevice* sim = i < bench_sims_.size() ? bench_sims_[i].get() : nullptr;
      const DeviceSpec& h = d.hw;
      if (!sim) {
        if (!opt_.quiet) std::cerr << "note: device '" << d.name << "' has no sim = ...: nothing presents it\n";
        continue;
      }
      if (d.type == "usb_midi" && d.sim == "nanokontrol2") {
        bench_dev[i] = bench_->add_usb_midi({h.vid >= 0 ? h.vid : 0x0944, h.pid >= 0 ? h.pid : 0x0117, false});
      } else if (d.type == "hid" && (d.sim == "gamepad" || d.sim == "pen_tablet")) {
        const int pid = h.pid >= 0 ? h.pid : h.pids.empty() ? 0x0001 : h.pids[0];
        bench_dev[i] = bench_->add_hid({h.vid >= 0 ? h.vid : 0x1209, pid, h.product.empty() ? d.name : h.product, h.serial,
                                        static_cast<HidDeviceSim&>(*sim).descriptor_bytes()});
      } else if (d.type == "gpio" && d.sim == "knob_box") {
        VirtualBench::Gpio g;
        g.label = h.chip;
        // The knob box's lines 3(k-1) = A, +1 = B, +2 = switch, named as the show names them.
        for (int k = 0; k < 4; ++k) {
          const bool enc = size_t(k) < h.encoders.size(), sw = size_t(k) < h.buttons.size();
          g.lines.push_back(enc ? h.encoders[size_t(k)].a : "UNUSED" + std::to_string(3 * k));
          g.lines.push_back(enc ? h.encoders[size_t(k)].b : "UNUSED" + std::to_string(3 * k + 1));
          g.lines.push_back(sw ? h.buttons[size_t(k)] : "UNUSED" + std::to_string(3 * k + 2));
        }
        bench_dev[i] = bench_->add_gpio(g);
      } else if (d.type == "tablet" && d.sim == "pen_tablet") {
        VirtualBench::Evdev e;
        if (!h.product.empty()) e.name = h.product;
        bench_dev[i] = bench_->add_evdev(e);
      } else if (!opt_.quiet) {
        std::cerr << "note: device '" << d.name << "': --simulate cannot present a " << d.sim << " as " << d.type << "\n";
      }
    }
  }
  devices_ = std::make_unique<DeviceSet>(epoch_ns_);
  hw_index_.assign(show_.devices.size(), -1);
  for (size_t i : hw) {
    std::string err;
    auto b = make_backend(show_.devices[i].hw, uint16_t(i), &err);
    if (!b) return show_.path + ":" + std::to_string(show_.devices[i].line) + ": " + err;
    hw_index_[i] = int(devices_->size());
    devices_->add(std::move(b));
  }
  hw_events_.resize(4096);
  devices_->start();
  for (size_t i : hw) {
    const DeviceState st = devices_->state(size_t(hw_index_[i]));
    if (st != DeviceState::Connected && !opt_.quiet)
      std::cerr << "device '" << show_.devices[i].name << "': " << device_state_name(st) << ": "
                << devices_->problem(size_t(hw_index_[i])) << (st == DeviceState::Waiting ? " (waiting for it)" : "") << "\n";
  }
  if (bench_) {
    for (size_t i : hw) {
      if (bench_dev[i] < 0) continue;
      SimDevice& sim = *bench_sims_[i];
      if (show_.devices[i].type == "tablet") {
        // Pen reports are re-expressed as evdev events by a feeder thread of the bench.
        auto& pen = static_cast<HidDeviceSim&>(sim);
        bench_thread_ = std::thread([this, dev = bench_dev[i], &pen] {
          auto dec = WireDecoder::hid(pen.descriptor(), 0);
          VirtualBench::Evdev geom;
          pen.drain(INT64_MAX, [&](const WireRecord& r) {
            while (!quit_requested() && !bench_stop_ && monotonic_ns() < epoch_ns_ + r.t_ns)
              std::this_thread::sleep_for(std::chrono::microseconds(500));
            if (!bench_stop_) present_pen_as_evdev(*bench_, dev, r, epoch_ns_, *dec, geom);
          });
        });
      } else {
        bench_->play(bench_dev[i], sim, epoch_ns_);
      }
    }
  }
  sdl_input_window(canvas_ && canvas_->is_window());
  return {};
}

void LiveShow::feedback() {
  // Controllers with feedback = true get their note/CC input echoed back (button LEDs follow).
  for (size_t k = 0; k < n_events_; ++k) {
    const Event& e = events_[k];
    if (e.source >= hw_index_.size() || hw_index_[e.source] < 0 || !show_.devices[e.source].hw.feedback) continue;
    uint8_t m[3] = {0, uint8_t(e.number & 0x7F), uint8_t(e.value & 0x7F)};
    if (e.kind == ControlKind::MidiCC) m[0] = uint8_t(0xB0 | e.channel);
    else if (e.kind == ControlKind::MidiNoteOn) m[0] = uint8_t(0x90 | e.channel);
    else if (e.kind == ControlKind::MidiNoteOff) m[0] = uint8_t(0x80 | e.channel);
    else continue;
    devices_->backend(size_t(hw_index_[e.source])).send_midi(m);
  }
}

}  // namespace mar
