// --simulate: a show's hardware devices presented at the kernel interface (the virtual
// bench, umockdev) and played by their simulators, so the real backends read them. The
// bench lives in a library the shipping `marionette` program does not link: that program
// hands --simulate runs to `marionette-simulate` (installed beside it), which links the
// bench and registers it here.
#pragma once

#include "app/show.h"
#include "firmware_sim/sim_device.h"

#include <memory>
#include <string>

namespace mar {

class HardwareSimulation {
 public:
  virtual ~HardwareSimulation() = default;
  /// Presents show device `d` (a hardware type) played by `sim`. Returns an empty string,
  /// or a note saying why it cannot be presented (the device then stays absent).
  virtual std::string present(const ShowDevice& d, SimDevice& sim) = 0;
  /// Starts playing every presented device (show time 0 = `epoch_mono_ns`): in real time, or
  /// in lockstep with the show's virtual clock, writing only what allow() lets through. In
  /// lockstep the hidraw and USB reads carry the show time the script gave each record (a
  /// read clock, devices/device.h), as GPIO and evdev events carry it in their timestamps.
  virtual void play(int64_t epoch_mono_ns, bool lockstep) = 0;
  /// Lockstep: the devices may write what they do through show time `t`.
  virtual void allow(int64_t t) = 0;
  /// The show time through which every presented device's timeline has been written at
  /// the kernel interface and can be read (INT64_MAX once all have ended). The players are
  /// threads that can fall behind on a busy machine; a frame at `t` waits for `t` first, as a
  /// real kernel has every event stamped before `t` queued by then. Called by the show's
  /// thread between play() and stop().
  virtual int64_t written_through() const = 0;
  /// Stops playing (joins the players); the devices stay plugged until destruction.
  virtual void stop() = 0;
  /// Hands each simulator what the show sent its device since the last call (a USB-MIDI
  /// controller's lights: SimDevice::receive), so it shows them. Between frames (allocates).
  virtual void deliver_sent() {}
};

/// Makes the simulation; nullptr with `error` set when this program cannot simulate.
using SimulationFactory = std::unique_ptr<HardwareSimulation> (*)(std::string* error);
void set_simulation_factory(SimulationFactory f);
std::unique_ptr<HardwareSimulation> make_simulation(std::string* error);
bool simulation_available();

/// marionette-simulate's start: re-executes under umockdev's preload when needed and
/// registers the virtual bench (defined in the marionette_simulate library).
void enable_virtual_bench(char** argv);

/// The shipping program's --simulate: replaces this process with `marionette-simulate`
/// from the same directory and the same arguments. Returns only on failure (exit code).
int exec_simulator(char** argv);

}  // namespace mar
