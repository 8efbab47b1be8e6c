// A simulated microphone: what a capture device would deliver — blocks of mono 16-bit PCM at
// 22,050 Hz (AudioPcm records, 48 samples each, silence between sounds) — from a WAV file
// played from time 0 and from a script's lines, each at its time:
//   0.5 say "Hello, I sing"            espeak-ng speaks it (voice en; `voice en+f3` at the end)
//   3.0 play other.wav                 another file (relative to the show)
// Speech is synthesised once, at load. Refused with the line or the file's name: a WAV that is
// not PCM, 8 to 48 kHz, 16-bit, mono or stereo; a say with nothing to say; espeak-ng missing
// (it names the Debian package).
#pragma once

#include "firmware_sim/sim_device.h"

#include <span>
#include <string>
#include <vector>

namespace mar {

/// A WAV file's samples, mono 16-bit at its own rate. Errors name the file.
Result<std::vector<int16_t>> read_wav(const std::string& path, int& rate);

class MicrophoneSim final : public SimDevice {
 public:
  static constexpr int kRate = 22050;
  /// `file`: a WAV played from 0 (empty: none); `dir`: where `play` files are.
  static Result<std::unique_ptr<MicrophoneSim>> make(const std::string& file, const std::string& dir);
  const char* kind() const override { return "microphone"; }
  WireKind wire() const override { return WireKind::AudioPcm; }
  DecoderConfig decoder_config() const override {
    DecoderConfig c;
    c.kind = WireKind::AudioPcm;
    c.audio_rate = kRate;
    c.voice = voice_;
    return c;
  }
  void set_voice(const std::array<std::array<double, 2>, 5>& v) override { voice_ = v; }
  /// The whole track (tests).
  const std::vector<int16_t>& track() const { return track_; }

 protected:
  Result<bool> action(double t, const std::vector<std::string>& w) override;

 private:
  MicrophoneSim() = default;
  void place(double t, std::span<const int16_t> pcm);
  void rebuild();
  std::string dir_;
  std::vector<int16_t> track_;
  std::array<std::array<double, 2>, 5> voice_{};
};

}  // namespace mar
