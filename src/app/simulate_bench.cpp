// The virtual bench behind --simulate (linked by marionette-simulate and the tests only).
#include "app/simulate.h"
#include "firmware_sim/midi_controller.h"
#include "devices/device.h"
#include "devices/vbench.h"
#include "firmware_sim/hid_device.h"
#include "input/hid_usages.h"

#include <linux/input.h>

#include <atomic>
#include <algorithm>
#include <chrono>
#include <deque>
#include <thread>

namespace mar {
namespace {

// A pen simulator's HID reports as evdev events (the bench's evdev node).
void present_pen_as_evdev(VirtualBench& bench, int dev, const WireRecord& r, int64_t epoch, Decoder& dec,
                          const VirtualBench::Evdev& geom) {
  dec.feed(r, [&](const Event& e) {
    if (e.kind != ControlKind::HidValue) return;
    const double u = normalized(e);
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

class BenchSimulation final : public HardwareSimulation {
 public:
  ~BenchSimulation() override { stop(); }

  std::string present(const ShowDevice& d, SimDevice& sim) override {
    const DeviceSpec& h = d.hw;
    if (d.type == "usb_midi" && midi_model(d.sim)) {
      played_.push_back({bench_.add_usb_midi({h.vid >= 0 ? h.vid : 0x0944, h.pid >= 0 ? h.pid : 0x0117, false}), &sim, false});
    } else if (d.type == "hid" && (d.sim == "gamepad" || d.sim == "pen_tablet")) {
      const int pid = h.pid >= 0 ? h.pid : h.pids.empty() ? 0x0001 : h.pids[0];
      played_.push_back({bench_.add_hid({h.vid >= 0 ? h.vid : 0x1209, pid, h.product.empty() ? d.name : h.product, h.serial,
                                         static_cast<HidDeviceSim&>(sim).descriptor_bytes()}),
                         &sim, false});
    } else if (d.type == "gpio" && d.sim == "knob_box") {
      VirtualBench::Gpio g;
      g.label = h.chip;
      // The chip's lines are the knob box's, named as the show names them (the box's own
      // layout says which line is which encoder phase or switch).
      const GpioLayout lay = sim.decoder_config().gpio;
      auto name = [&](int line, const std::string& given) {
        if (size_t(line) >= g.lines.size()) g.lines.resize(size_t(line) + 1);
        g.lines[size_t(line)] = given;
      };
      for (size_t e = 0; e < lay.encoders.size(); ++e) {
        const bool have = e < h.encoders.size();
        name(lay.encoders[e].line_a, have ? h.encoders[e].a : "");
        name(lay.encoders[e].line_b, have ? h.encoders[e].b : "");
      }
      for (size_t b = 0; b < lay.buttons.size(); ++b) name(lay.buttons[b], b < h.buttons.size() ? h.buttons[b] : "");
      for (size_t l = 0; l < g.lines.size(); ++l)
        if (g.lines[l].empty()) g.lines[l] = "UNUSED" + std::to_string(l);
      played_.push_back({bench_.add_gpio(g), &sim, false});
    } else if (d.type == "tablet" && d.sim == "pen_tablet") {
      VirtualBench::Evdev e;
      if (!h.product.empty()) e.name = h.product;
      played_.push_back({bench_.add_evdev(e), &sim, true});
    } else {
      return "--simulate cannot present a " + d.sim + " as " + d.type;
    }
    return {};
  }

  void play(int64_t epoch, bool lockstep) override {
    if (lockstep) {
      clock_ = &bench_.read_clock();
      set_read_clock(clock_);
    }
    for (const Played& p : played_) {
      if (!p.as_evdev) {
        bench_.play(p.dev, *p.sim, epoch, lockstep);
        continue;
      }
      // Pen reports are re-expressed as evdev events by a feeder thread per tablet.
      auto& pen = static_cast<HidDeviceSim&>(*p.sim);
      std::atomic<int64_t>& written = fed_.emplace_back(-1);
      feeders_.emplace_back([this, dev = p.dev, &pen, epoch, lockstep, &written] {
        auto dec = make_hid_decoder(pen.descriptor(), 0);
        VirtualBench::Evdev geom;
        const std::atomic<int64_t>& allowed = bench_.allowed();
        pen.drain(INT64_MAX, [&](const WireRecord& r) {
          written.store(r.t_ns - 1, std::memory_order_release);  // everything before r is out
          if (lockstep) {
            for (int64_t a; !stop_ && (a = allowed.load(std::memory_order_acquire)) < r.t_ns;) allowed.wait(a);
          } else {
            while (!stop_ && monotonic_ns() < epoch + r.t_ns) std::this_thread::sleep_for(std::chrono::microseconds(500));
          }
          if (!stop_) present_pen_as_evdev(bench_, dev, r, epoch, *dec, geom);
        });
        written.store(INT64_MAX, std::memory_order_release);
      });
    }
  }

  void allow(int64_t t) override { bench_.allow_through(t); }

  void deliver_sent() override {
    // The players hear what the show sends as it goes (a nanoKONTROL2 answers its scene
    // requests); stopping them delivers the rest.
    stop();
  }

  int64_t written_through() const override {
    int64_t t = bench_.written_through();
    for (const auto& w : fed_) t = std::min(t, w.load(std::memory_order_acquire));
    return t;
  }

  void stop() override {
    stop_ = true;
    if (clock_) set_read_clock(nullptr);  // (the bench keeps it until it goes)
    clock_ = nullptr;
    bench_.stop_playing();  // also wakes the feeders that wait for the show
    for (auto& t : feeders_)
      if (t.joinable()) t.join();
    feeders_.clear();
    fed_.clear();
  }

 private:
  struct Played {
    int dev;
    SimDevice* sim;
    bool as_evdev;
  };
  VirtualBench bench_;
  std::vector<Played> played_;
  std::vector<std::thread> feeders_;
  std::deque<std::atomic<int64_t>> fed_;  ///< per feeder: show time written through
  std::atomic<bool> stop_{false};
  ReadClock* clock_ = nullptr;  ///< installed while playing in lockstep
};

std::unique_ptr<HardwareSimulation> make_bench(std::string* error) {
  if (!VirtualBench::preload_active()) {
    *error = "--simulate needs umockdev's preload (marionette-simulate re-executes itself with it)";
    return nullptr;
  }
  return std::make_unique<BenchSimulation>();
}

}  // namespace

void enable_virtual_bench(char** argv) {
  if (argv) VirtualBench::ensure_preload(argv);
  set_simulation_factory(&make_bench);
}

}  // namespace mar
