// Per-binding signal filters.
#pragma once

#include <cmath>
#include <cstdint>

namespace mar {

/// One Euro filter (Casiez, Roussel, Vogel, CHI 2012): a low-pass whose cutoff rises with
/// speed — smooth when still, little lag when moving. Times from event timestamps.
struct OneEuro {
  double min_cutoff = 1.0;  ///< Hz
  double beta = 0.0;        ///< cutoff increase per unit/s of speed
  double d_cutoff = 1.0;    ///< Hz, for the speed estimate
  bool enabled = false;

  double filter(double x, int64_t t_ns) {
    if (!enabled) return x;
    if (!primed_) {
      primed_ = true;
      x_ = x;
      dx_ = 0;
      t_ = t_ns;
      return x;
    }
    const double dt = (double(t_ns) - double(t_)) * 1e-9;  // (no int64 overflow at the limits)
    t_ = t_ns;
    if (dt <= 0) return x_;
    const double dx = (x - x_) / dt;
    dx_ += alpha(d_cutoff, dt) * (dx - dx_);
    const double cutoff = min_cutoff + beta * std::fabs(dx_);
    x_ += alpha(cutoff, dt) * (x - x_);
    return x_;
  }
  void reset() { primed_ = false; }

 private:
  static double alpha(double cutoff, double dt) {
    const double tau = 1.0 / (2 * M_PI * cutoff);
    return 1.0 / (1.0 + tau / dt);
  }
  bool primed_ = false;
  double x_ = 0, dx_ = 0;
  int64_t t_ = 0;
};

/// Relative-encoder encodings of a 7-bit CC value as a signed delta.
enum class RelativeMode : uint8_t {
  Absolute,        ///< not relative
  TwosComplement,  ///< 1..63 up, 127..64 = -1..-64
  BinaryOffset,    ///< 64 = 0, 65.. up, 63.. down
  SignMagnitude,   ///< bit 6 set = negative, bits 0-5 magnitude
  SignMagnitudeInv,///< bit 6 set = positive
  Delta,           ///< the event value is already a signed delta (encoders, relative HID)
};

inline int relative_delta(RelativeMode m, int v) {
  switch (m) {
    case RelativeMode::TwosComplement: return v < 64 ? v : v - 128;
    case RelativeMode::BinaryOffset: return v - 64;
    case RelativeMode::SignMagnitude: return (v & 0x40) ? -(v & 0x3F) : (v & 0x3F);
    case RelativeMode::SignMagnitudeInv: return (v & 0x40) ? (v & 0x3F) : -(v & 0x3F);
    case RelativeMode::Delta: return v;
    case RelativeMode::Absolute: break;
  }
  return 0;
}

}  // namespace mar
