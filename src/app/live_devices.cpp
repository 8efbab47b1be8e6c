// The live show's hardware devices: backends in a DeviceSet, and for --simulate the show's
// simulators presented at the kernel interface (app/simulate.h).
#include "app/live.h"
#include "devices/backends.h"
#include "app/sim_source.h"
#include "app/simulate.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <thread>

namespace mar {
namespace {

std::atomic<bool> g_quit{false}, g_reload{false};
void on_signal(int) { g_quit = true; }
void on_hangup(int) { g_reload = true; }

}  // namespace

void install_quit_handler() {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::signal(SIGHUP, on_hangup);
}
bool quit_requested() { return g_quit.load(); }
bool take_reload_request() { return g_reload.exchange(false); }

std::string LiveShow::open_devices() {
  // Every show device is a source in one DeviceSet (source = show device index): hardware
  // backends, and in-process simulators for `type = "sim"` devices. With --simulate the
  // hardware devices' simulators are presented at the kernel interface instead, and the
  // real backends read them.
  // Device timestamps are on this clock. A whole microsecond: evdev stamps in microseconds, and
  // a simulated device's times then come back exactly, whatever the epoch was.
  if (has_hardware_) pacer_.set_epoch(monotonic_ns() / 1000 * 1000);
  if (opt_.simulate && has_hardware_) {
    std::string err;
    if (!(simulation_ = make_simulation(&err))) return err;
    for (size_t i = 0; i < show_.devices.size(); ++i) {
      const ShowDevice& d = show_.devices[i];
      if (d.type == "sim") continue;
      SimDevice* sim = i < sims_.size() ? sims_[i].get() : nullptr;
      const std::string note = sim ? simulation_->present(d, *sim) : "has no sim = ...: nothing presents it";
      if (!note.empty() && !opt_.quiet) std::cerr << "note: device '" << d.name << "': " << note << "\n";
    }
  }
  devices_ = std::make_unique<DeviceSet>(pacer_.epoch());
  for (size_t i = 0; i < show_.devices.size(); ++i) {
    const ShowDevice& d = show_.devices[i];
    if (d.type == "sim") {
      devices_->add(std::make_unique<SimSource>(*sims_[i], d.hw, uint16_t(i), int64_t(d.debounce_ms * 1e6)));
      continue;
    }
    std::string err;
    auto b = make_backend(d.hw, uint16_t(i), &err);
    if (!b) return show_.path + ":" + std::to_string(d.line) + ": " + err;
    devices_->add(std::move(b));
  }
  devices_->start();
  for (size_t i = 0; i < show_.devices.size(); ++i) {
    const DeviceState st = devices_->state(i);
    if (st != DeviceState::Connected && !opt_.quiet)
      std::cerr << "device '" << show_.devices[i].name << "': " << device_state_name(st) << ": " << devices_->problem(i)
                << (st == DeviceState::Waiting ? " (waiting for it)" : "") << "\n";
  }
  if (simulation_) simulation_->play(pacer_.epoch(), !realtime());
  sdl_input_window(canvas_ && canvas_->is_window());
  return {};
}

void LiveShow::await_simulation(int64_t t) {
  // --simulate: the frame at `t` reads what the simulated devices did by `t`, however far
  // their player threads fell behind on a busy machine. Outside the frame, like the pacer's
  // wait, and bounded so that a stuck player cannot stop the show: a second on the wall clock
  // (frames late for it are counted), ten on the virtual clock, where the players write only
  // what the frame allows (lockstep) and every frame waits for them.
  if (!simulation_) return;
  const bool lockstep = !realtime();
  if (lockstep) simulation_->allow(t);
  if (simulation_->written_through() >= t) return;
  const int64_t start = monotonic_ns(), give_up = start + (lockstep ? 10'000'000'000 : 1'000'000'000);
  if (!lockstep) ++sim_waits_;
  for (int spin = 0; simulation_->written_through() < t; ++spin) {
    if (!lockstep) sim_max_wait_ms_ = std::max(sim_max_wait_ms_, double(monotonic_ns() - start) * 1e-6);
    if (monotonic_ns() >= give_up) {
      if (sim_timeouts_++ == 0 && !opt_.quiet)
        std::cerr << "warning: --simulate: the simulated devices were not written through " << double(t) * 1e-9
                  << " s after " << (lockstep ? 10 : 1) << " s of waiting; the show goes on without them\n";
      return;
    }
    if (spin < 50) std::this_thread::yield();
    else std::this_thread::sleep_for(std::chrono::microseconds(20));
  }
}

bool LiveShow::tell_takeover_waits(int64_t t_ns) {
  // A control that has not picked its target up yet does nothing until it gets there. One that
  // is still waiting a second after its first wait is said once, with where to move it (a fader
  // on its way through the target picks it up sooner and is not). The HUD shows it while it
  // waits. No allocation.
  bool pending = false;
  for (size_t i = 0; i < mapping_.binding_count(); ++i) {
    Binding& b = mapping_.bindings()[i];
    if (b.takeover_told != 1) continue;
    if (b.engaged) {
      b.takeover_told = 2;
      continue;
    }
    if (t_ns - b.takeover_since < 1'000'000'000) {
      pending = true;
      continue;
    }
    b.takeover_told = 2;
    if (opt_.quiet) continue;
    const double at = mapping_.takeover_at(i);
    char line[512];
    std::snprintf(line, sizeof line,
                  "note: %s:%d: '%s' -> %s waits for soft takeover: move it to %.0f %% to pick the target up "
                  "(takeover = false makes it jump)\n",
                  show_.path.c_str(), b.line, b.control.text.c_str(), b.target_text.c_str(), at < 0 ? 0.0 : at * 100);
    std::fputs(line, stderr);
  }
  return pending;
}

void LiveShow::feedback() {
  // Controllers with feedback = true get their note/CC input echoed back (button LEDs follow).
  for (size_t k = 0; k < n_events_; ++k) {
    const Event& e = events_[k];
    if (e.source >= show_.devices.size() || !show_.devices[e.source].hw.feedback) continue;
    uint8_t m[3] = {0, uint8_t(e.number & 0x7F), uint8_t(e.value & 0x7F)};
    if (e.kind == ControlKind::MidiCC) m[0] = uint8_t(0xB0 | e.channel);
    else if (e.kind == ControlKind::MidiNoteOn) m[0] = uint8_t(0x90 | e.channel);
    else if (e.kind == ControlKind::MidiNoteOff) m[0] = uint8_t(0x80 | e.channel);
    else continue;
    devices_->backend(e.source).send_midi(m);
  }
}

}  // namespace mar
