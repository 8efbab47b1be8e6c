// A knob box: 4 mechanical rotary encoders with push buttons, wired to GPIO lines with
// pull-ups (idle high; a detent rests at A = B = 1; a pressed button reads 0). Encoder k
// (1-4) uses lines 3(k-1) (A), 3(k-1)+1 (B) and 3(k-1)+2 (button). 4 quarter steps per
// detent. Contact bounce: after each edge the moving contact chatters for a random
// 0.2..bounce_ms (never past half the gap to the next edge) and settles at its new level.
#pragma once

#include "firmware_sim/sim_device.h"

#include <random>

namespace mar {

class KnobBoxSim : public SimDevice {
 public:
  static constexpr int kEncoders = 4;
  static constexpr int kLines = 3 * kEncoders;
  explicit KnobBoxSim(double bounce_ms = 0, uint32_t seed = 1) : bounce_ms_(bounce_ms), rng_(seed) {}
  const char* kind() const override { return "knob_box"; }
  WireKind wire() const override { return WireKind::GpioEdge; }
  /// Knob k (1..4): lines 3(k-1) = A, +1 = B, +2 = its push switch.
  DecoderConfig decoder_config() const override {
    DecoderConfig c;
    c.kind = WireKind::GpioEdge;
    for (int e = 1; e <= 4; ++e) {
      c.gpio.encoders.push_back({3 * (e - 1), 3 * (e - 1) + 1, 4});
      c.gpio.buttons.push_back(3 * (e - 1) + 2);
    }
    return c;
  }
  /// Turns encoder `enc` (1-4) by `detents` (sign = direction) evenly over `dur_s`.
  void turn(int enc, double t_s, int detents, double dur_s);
  /// Presses encoder `enc`'s push button at `t_s` for `hold_s`.
  void press(int enc, double t_s, double hold_s);
  static int line_a(int enc) { return 3 * (enc - 1); }
  static int line_b(int enc) { return 3 * (enc - 1) + 1; }
  static int line_button(int enc) { return 3 * (enc - 1) + 2; }

 protected:
  Result<bool> action(double t, const std::vector<std::string>& w) override;

 private:
  void edge(int64_t t, int line, int level, int64_t room_ns);
  double bounce_ms_;
  std::mt19937 rng_;
  int phase_[kEncoders] = {2, 2, 2, 2};  ///< Gray index per encoder (2 = 11)
};

}  // namespace mar
