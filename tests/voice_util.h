// Helpers for the voice tests: espeak-ng's speech as PCM (through the microphone simulator's WAV
// reader) and WAV files written for the simulated microphone to play.
#pragma once

#include "firmware_sim/microphone.h"
#include "test_util.h"

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

namespace mar::test {

inline bool have_espeak() { return std::system("command -v espeak-ng >/dev/null 2>&1") == 0; }

/// espeak-ng's `phonemes` ("a:") in `voice` at `pitch` (0-99) and `speed` (words a minute);
/// empty when espeak-ng fails. `rate` gets its sample rate.
inline std::vector<int16_t> speak(const std::string& voice, const std::string& phonemes, int pitch, int speed, int& rate) {
  const std::string wav = (temp_dir("voice") / "v.wav").string();
  const std::string cmd = "espeak-ng -v '" + voice + "' -p " + std::to_string(pitch) + " -s " + std::to_string(speed) + " -w '" + wav +
                          "' '[[" + phonemes + "]]' 2>/dev/null";
  if (std::system(cmd.c_str()) != 0) return {};
  auto pcm = read_wav(wav, rate);
  return pcm.ok() ? *pcm.value : std::vector<int16_t>{};
}

/// A WAV file of `data` (the samples' bytes as stored), with the header's fields as given (a
/// test may write one the microphone must refuse).
inline std::string write_wav(const std::string& path, const std::vector<char>& data, int rate, uint16_t format = 1, uint16_t bits = 16,
                             uint16_t channels = 1) {
  std::ofstream o(path, std::ios::binary);
  auto u32 = [&](uint32_t v) { o.write(reinterpret_cast<const char*>(&v), 4); };
  auto u16 = [&](uint16_t v) { o.write(reinterpret_cast<const char*>(&v), 2); };
  o.write("RIFF", 4);
  u32(uint32_t(36 + data.size()));
  o.write("WAVEfmt ", 8);
  u32(16);
  u16(format);
  u16(channels);
  u32(uint32_t(rate));
  u32(uint32_t(rate * channels * bits / 8));
  u16(uint16_t(channels * bits / 8));
  u16(bits);
  o.write("data", 4);
  u32(uint32_t(data.size()));
  o.write(data.data(), long(data.size()));
  return path;
}

/// Mono 16-bit PCM as a WAV file (little-endian, as the machines here are).
inline std::string write_wav(const std::string& path, const std::vector<int16_t>& pcm, int rate) {
  std::vector<char> data(pcm.size() * 2);
  for (size_t i = 0; i < pcm.size(); ++i) {
    data[2 * i] = char(pcm[i] & 0xFF);
    data[2 * i + 1] = char((pcm[i] >> 8) & 0xFF);
  }
  return write_wav(path, data, rate);
}

}  // namespace mar::test
