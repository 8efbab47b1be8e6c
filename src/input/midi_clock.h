// Tempo and beat phase from MIDI clock (0xF8 timing clock at 24 a quarter note, 0xFA start,
// 0xFB continue, 0xFC stop). The tick times jitter (a USB stack, a busy sender), so the clock is
// a least-squares line through the last 96 ticks (four beats): the slope is the tick period (the
// tempo) and the line, not the last tick, says where the beat is. A tick far off the line (a tempo
// change, a gap) starts the line afresh. Ticks go on while the transport is stopped (the tempo
// stays known); the song position does not. A sender that never sends start counts from its
// first tick. Allocation-free.
#pragma once

#include <array>
#include <cstdint>

namespace mar {

class MidiClock {
 public:
  static constexpr int kPerBeat = 24;
  static constexpr int kWindow = 96;

  /// Feeds a system real-time byte (F8, FA, FB, FC; others are ignored). Returns true for a tick.
  bool feed(uint8_t status, int64_t t_ns);
  void tick(int64_t t_ns);  ///< 0xF8
  void start();             ///< 0xFA: the song from its beginning; the next tick is beat 0
  void resume();            ///< 0xFB: on from where it stopped
  void stop();              ///< 0xFC: the position holds

  bool running() const { return running_; }
  /// A tempo is known (at least 6 ticks on one line).
  bool locked() const { return n_ >= 6; }
  double bpm() const;
  /// Beats of the song at time `t_ns` (on the fitted line; held while stopped).
  double beats_at(int64_t t_ns) const;
  /// 0..1 within the beat, and within a bar of `beats_per_bar` beats.
  double beat_phase(int64_t t_ns) const;
  double bar_phase(int64_t t_ns, int beats_per_bar = 4) const;
  /// The fitted time of the last tick received, ns.
  double last_tick_time_ns() const { return time_of_seq(double(seq_ - 1)); }
  /// The fitted time of the song's tick `k` (0 = the first tick after start), ns.
  double tick_time_ns(double k) const { return time_of_seq(k + double(zero_ + paused_)); }

 private:
  void fit();
  double time_of_seq(double s) const { return double(origin_) + a_ns_ + b_ns_ * (s - double(seq_ - n_)); }
  std::array<int64_t, kWindow> t_{};  ///< tick times by arrival (seq % kWindow)
  int64_t seq_ = 0;      ///< ticks received
  int n_ = 0;            ///< of them on the line (the last n_)
  int64_t zero_ = 0;     ///< seq of the song's tick 0
  int64_t paused_ = 0;   ///< ticks received while stopped (not song time)
  bool running_ = true;
  int64_t origin_ = 0;   ///< time of the line's oldest tick
  double a_ns_ = 0, b_ns_ = 0;
  double held_ = 0;      ///< the song's beats where it stopped
};

}  // namespace mar
