// HID devices driven by a real report descriptor: the simulator parses the descriptor with
// the same parser the program uses, keeps one state buffer per input report and writes
// each value into the bits the descriptor gives it, so the reports are what that device
// sends. Values are set by usage (page << 16 | id).
#pragma once

#include "firmware_sim/sim_device.h"
#include "input/hid.h"

namespace mar {

/// Standard usages the simulators and the mapping speak of.
namespace usage {
constexpr uint32_t X = hid_usage(0x01, 0x30), Y = hid_usage(0x01, 0x31), Z = hid_usage(0x01, 0x32);
constexpr uint32_t Rx = hid_usage(0x01, 0x33), Ry = hid_usage(0x01, 0x34), Rz = hid_usage(0x01, 0x35);
constexpr uint32_t Hat = hid_usage(0x01, 0x39), Wheel = hid_usage(0x01, 0x38), Dial = hid_usage(0x01, 0x37);
constexpr uint32_t TipPressure = hid_usage(0x0D, 0x30), InRange = hid_usage(0x0D, 0x32);
constexpr uint32_t TipSwitch = hid_usage(0x0D, 0x42), BarrelSwitch = hid_usage(0x0D, 0x44);
constexpr uint32_t XTilt = hid_usage(0x0D, 0x3D), YTilt = hid_usage(0x0D, 0x3E);
constexpr uint32_t button(int n) { return hid_usage(0x09, uint16_t(n)); }
}  // namespace usage

/// Reads a descriptor file: whitespace-separated hex (.hex, .txt; `#` comments to the end of a
/// line) or raw bytes.
Result<std::vector<uint8_t>> read_descriptor_file(const std::string& path);

class HidDeviceSim : public SimDevice {
 public:
  WireKind wire() const override { return WireKind::HidReport; }
  DecoderConfig decoder_config() const override {
    DecoderConfig c;
    c.kind = WireKind::HidReport;
    c.hid_descriptor = bytes_;
    return c;
  }
  /// Parses the descriptor and resets every input report to its idle state.
  Result<bool> set_descriptor(std::span<const uint8_t> bytes);
  const HidDescriptor& descriptor() const { return desc_; }
  const std::vector<uint8_t>& descriptor_bytes() const { return bytes_; }
  /// Sets a usage to a logical value (clamped to the field's range). False if absent.
  bool set(uint32_t usage, int32_t logical);
  /// Sets a usage from 0..1 across its logical range (-1..1 for centred axes with `centred`).
  bool set_unit(uint32_t usage, double u);
  /// Emits the current state of the report that carries `usage`.
  void send(int64_t t_ns, uint32_t usage);
  bool has(uint32_t usage) const { return desc_.find_usage(usage) != nullptr; }

 protected:
  virtual void idle_state() {}
  HidDescriptor desc_;
  std::vector<uint8_t> bytes_;
  std::vector<std::vector<uint8_t>> state_;  ///< per descriptor report (inputs only used)
};

/// A pen tablet: x, y (0..1 of the active area), tip pressure, tip switch, in range.
/// Reports at `rate_hz` (200 by default) while the pen is in range.
class PenTabletSim : public HidDeviceSim {
 public:
  const char* kind() const override { return "pen_tablet"; }
  /// Pen down at the first point, through the points evenly over `dur_s`, then up
  /// (stays in range). `pressure` 0..1.
  void stroke(const std::vector<std::pair<double, double>>& pts, double t_s, double dur_s, double pressure);
  void hover(double x, double y, double t_s);
  void leave(double t_s);  ///< out of range
  double rate_hz = 200;

 protected:
  Result<bool> action(double t, const std::vector<std::string>& w) override;

 private:
  void report(int64_t t, double x, double y, double pressure, bool tip, bool range);
};

/// A gamepad: sticks (left = X/Y, right = Z/Rz or Rx/Ry), hat, buttons 1..n. Idle sticks
/// are centred, the hat is at its null state.
class GamepadSim : public HidDeviceSim {
 public:
  const char* kind() const override { return "gamepad"; }
  /// Moves a stick ("left" or "right") to (x, y) in -1..1 over `dur_s` (reports at 250 Hz).
  void stick(const std::string& which, double x, double y, double t_s, double dur_s);
  void press(int button, double t_s, double hold_s);

 protected:
  Result<bool> action(double t, const std::vector<std::string>& w) override;
  void idle_state() override;

 private:
  double pos_[2][2] = {{0, 0}, {0, 0}};
};

}  // namespace mar
