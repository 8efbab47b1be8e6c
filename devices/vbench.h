// The virtual bench: presents devices at the kernel interface with umockdev, so the real
// backends (libusb, hidapi, libgpiod, libevdev) run unchanged against them. USB-MIDI is an
// emulated usbdevfs node answering URB ioctls, HID a hidraw node (sysfs descriptor +
// HIDIOCGRDESCSIZE, each read answered with one queued report), GPIO a gpiochip answering the v1 line
// ioctls (edges with our own timestamps through a pipe per line), a pen tablet an evdev
// node answering EVIOCG* (input_events written to the node).
//
// Needs umockdev's preload in the process: call VirtualBench::ensure_preload(argv) first
// thing in main (it re-executes the program with LD_PRELOAD set when it is missing).
#pragma once

#include "devices/device.h"
#include "firmware_sim/sim_device.h"

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace mar {

class VirtualBench {
 public:
  /// Re-executes the program under umockdev's preload when it is not loaded; returns
  /// (without re-executing) when already loaded. `argv` as given to main.
  static void ensure_preload(char** argv);
  static bool preload_active();

  VirtualBench();
  ~VirtualBench();
  VirtualBench(const VirtualBench&) = delete;
  VirtualBench& operator=(const VirtualBench&) = delete;

  struct UsbMidi {
    int vid = 0x0944, pid = 0x0117;  ///< Korg nanoKONTROL2
    bool kernel_driver = false;      ///< pretend snd-usb-audio holds the interface
  };
  struct Hid {
    int vid = 0x054c, pid = 0x09cc;
    std::string name = "Virtual HID", uniq;
    std::vector<uint8_t> descriptor;
  };
  struct Gpio {
    std::string label = "pinctrl-bcm2711";
    std::vector<std::string> lines;  ///< line names by offset
  };
  struct Evdev {
    std::string name = "Virtual Pen Tablet";
    int vid = 0x056a, pid = 0x0000;
    int x_max = 21600, y_max = 13500, pressure_max = 1023, tilt = 64;
  };
  /// Each returns the device's index on the bench (plugged in).
  int add_usb_midi(const UsbMidi& d);
  int add_hid(const Hid& d);
  int add_gpio(const Gpio& d);
  int add_evdev(const Evdev& d);

  /// Device output. USB: queued for the next bulk IN URB. HID: queued, one report per read
  /// (hidraw keeps report boundaries). GPIO/evdev: with the device timestamp
  /// (CLOCK_MONOTONIC ns). `show_t`: the show time the read clock gives the read (-1: none).
  void usb_in(int dev, std::span<const uint8_t> packets, int64_t show_t = -1);
  void hid_report(int dev, std::span<const uint8_t> report, int64_t show_t = -1);
  void gpio_edge(int dev, unsigned line, int level, int64_t mono_ns);
  void evdev_event(int dev, uint16_t type, uint16_t code, int32_t value, int64_t mono_ns);
  /// Writes a simulated device's record (USB-MIDI packets, a HID report or a GPIO edge).
  void write(int dev, const WireRecord& r, int64_t epoch_mono_ns);

  /// Bytes the program sent with bulk OUT transfers (USB).
  std::vector<uint8_t> usb_out(int dev);
  /// Handle flags of the line request (GPIO: GPIOHANDLE_REQUEST_BIAS_PULL_UP etc.).
  uint32_t gpio_flags(int dev, unsigned line);
  bool kernel_driver_detached(int dev);

  void unplug(int dev);
  void replug(int dev);
  bool plugged(int dev) const;
  /// Makes the device's node unreadable (mode 000, as a user finds a node without the
  /// udev rule). Root reads it anyway: see act_as_user().
  void deny(int dev, bool denied);
  /// Drops (or restores) the calling thread's CAP_DAC_OVERRIDE/CAP_DAC_READ_SEARCH so that
  /// file permissions apply to it and to threads it starts, as for a normal user.
  static void act_as_user(bool on);

  /// Plays `sim` into `dev` on a background thread (show time 0 = `epoch_mono_ns`): in real
  /// time, or in lockstep with a virtual clock — then it writes, as fast as it can, what the
  /// script does through the time allow_through() last gave, and waits for more. Stops with
  /// stop_playing() or the bench. A USB-MIDI simulator also hears what the host sends the
  /// device (SimDevice::receive) and its answers are written at once, until it is stopped.
  void play(int dev, SimDevice& sim, int64_t epoch_mono_ns, bool lockstep = false);
  /// Lockstep players may write through show time `t` (never goes back).
  void allow_through(int64_t t);
  /// The time lockstep players wait for (the `allowed` time a feeder of its own may follow).
  const std::atomic<int64_t>& allowed() const;
  void stop_playing();
  /// Whether every played timeline has been written.
  bool played_all() const;
  /// The show time through which every played timeline has been written (INT64_MAX when
  /// all have ended), and every USB packet written so far taken by its reader (the packets
  /// of a transfer libusb has not yet handed on hold it before their time): a reader at `t`
  /// no later than this sees what the devices did by `t`. hidraw, GPIO and evdev reads are
  /// answered at once, so what is written is readable.
  int64_t written_through() const;
  /// A read clock (devices/device.h) that stamps hidraw reports and IN transfers with the show
  /// time they were written for, and learns when an IN transfer was handed on. Covers the
  /// devices on the bench when it is called (nodes of later plugs and replugs fall back to the
  /// monotonic clock). Lives as long as the bench.
  ReadClock& read_clock();

  struct Impl;

 private:
  std::unique_ptr<Impl> p_;
};

}  // namespace mar
