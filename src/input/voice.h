// A voice's controls from PCM (docs/algorithms.md §8): the level (RMS of the last 10 ms in dBFS,
// attack and release smoothing), the vowel being sung or spoken as a viseme (a, i, u, e, o; closed below a gate),
// and an onset at a syllable's start. Analysis frames of 25 ms every 5 ms; the vowel from its
// first two formants (LPC at about 11 kHz, the envelope's first peaks), the nearest of five
// templates — adult averages by default, a voice's own after calibrate() — in log frequency,
// with hysteresis (a new vowel must win two frames running). Pure and allocation-free after
// construction: a decoder feeds it the PCM blocks a capture device or a simulated microphone
// delivers.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace mar {

enum class Viseme : uint8_t { Closed, A, I, U, E, O };
const char* viseme_name(Viseme v);

struct VoiceOptions {
  double gate_db = -42;              ///< below this level the mouth is closed
  double attack_s = 0, release_s = 0.12;  // (attack 0: a rise shows at once)
  double frame_s = 0.025, hop_s = 0.005;
  /// F1, F2 per vowel (A, I, U, E, O), Hz.
  std::array<std::array<double, 2>, 5> templates{{{750, 1200}, {300, 2300}, {320, 800}, {500, 1900}, {500, 900}}};
};

struct VoiceFrame {
  double t = 0;           ///< seconds from the first sample to the frame's end
  double level_db = -120; ///< smoothed
  Viseme viseme = Viseme::Closed;
  bool onset = false;     ///< the level rose through the gate: a syllable starts
  double f1 = 0, f2 = 0;  ///< the formants it heard (0: none)
};

class VoiceAnalyzer {
 public:
  VoiceAnalyzer(int sample_rate, const VoiceOptions& o = {});
  int sample_rate() const { return rate_; }
  /// Feeds samples; each completed frame is handed to `out` (called in order).
  template <class F>
  void push(std::span<const int16_t> pcm, F&& out) {
    for (int16_t s : pcm) {
      ring_[size_t(write_ % ring_.size())] = double(s) / 32768.0;
      ++write_;
      if (write_ % size_t(hop_n_) == 0) out(analyse());  // (before the first full frame, silence before it)
    }
  }
  /// The formants of a stretch of one vowel (the median over its voiced frames), for calibrate.
  static bool measure_vowel(int sample_rate, std::span<const int16_t> pcm, double& f1, double& f2, const VoiceOptions& o = {});
  /// Takes a voice's own F1, F2 for vowel `v` (A..O).
  void calibrate(Viseme v, double f1, double f2);
  const VoiceOptions& options() const { return o_; }

 private:
  VoiceFrame analyse();
  bool formants(double& f1, double& f2);
  Viseme nearest(double f1, double f2) const;
  VoiceOptions o_;
  int rate_, frame_n_, hop_n_, decim_;
  std::vector<double> ring_, frame_, dec_, env_;
  size_t write_ = 0;
  double level_ = -90;
  bool open_ = false;
  Viseme shown_ = Viseme::Closed, candidate_ = Viseme::Closed;
  int candidate_frames_ = 0;
};

}  // namespace mar
