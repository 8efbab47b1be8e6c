// The simulated microphone: WAV files and espeak-ng speech as PCM blocks on the show clock,
// silence between and after; what it refuses, with the file or the line; and its blocks decode
// into a voice's controls (level, visemes, onsets) as a capture device's would.
#include "firmware_sim/microphone.h"
#include "input/decoder.h"
#include "voice_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>

namespace mar {
namespace {

// A WAV file: `bits` per sample, `format` (1: PCM), `channels`, `rate`, `samples` of a 220 Hz tone.
std::string write_wav(const std::string& name, int rate, int samples, uint16_t format = 1, uint16_t bits = 16, uint16_t channels = 1) {
  std::vector<char> data;
  for (int i = 0; i < samples; ++i)
    for (int c = 0; c < channels; ++c) {
      const int16_t s = int16_t(8000 * std::sin(2 * M_PI * 220 * i / rate));
      data.push_back(char(s & 0xFF));
      data.push_back(char((s >> 8) & 0xFF));
    }
  return test::write_wav((test::temp_dir("wav") / name).string(), data, rate, format, bits, channels);
}

TEST(Microphone, AWavPlaysFromZeroAsBlocksThenSilence) {
  const std::string wav = write_wav("tone.wav", 44100, 44100 / 2, 1, 16, 2);  // half a second, stereo, 44.1 kHz
  auto m = MicrophoneSim::make(wav, "");
  ASSERT_TRUE(m.ok()) << m.error;
  const auto& tl = (*m.value)->timeline();
  ASSERT_FALSE(tl.empty());
  EXPECT_NEAR(double((*m.value)->track().size()) / MicrophoneSim::kRate, 0.5, 0.001) << "resampled to 22,050 Hz";
  EXPECT_NEAR(double(tl.back().t_ns) * 1e-9, 1.0, 0.01) << "half a second of sound, half of silence";
  for (size_t i = 1; i < tl.size(); ++i) ASSERT_LE(tl[i - 1].t_ns, tl[i].t_ns);
  EXPECT_EQ(tl[0].kind, WireKind::AudioPcm);
  // decoded as a capture device's blocks: the level rises, a viseme shows, an onset fires
  DecoderConfig c = (*m.value)->decoder_config();
  auto parsed = DecoderConfig::parse(c.serialize());
  ASSERT_TRUE(parsed.ok()) << parsed.error;
  EXPECT_EQ(parsed.value->audio_rate, MicrophoneSim::kRate);
  auto dec = make_decoder(*parsed.value, 0);
  ASSERT_TRUE(dec);
  int32_t top = 0;
  bool onset = false, opened = false, closed_again = false;
  for (const WireRecord& r : tl)
    dec->feed(r, [&](const Event& e) {
      if (e.number == voice_usage::kLevel) top = std::max(top, e.value);
      if (e.number == voice_usage::kOnset && e.value) onset = true;
      if (e.number != voice_usage::kLevel && e.number != voice_usage::kOnset && e.value == 1)
        (e.number == voice_usage::viseme(Viseme::Closed) ? (opened ? closed_again : opened) : opened) = true;
    });
  EXPECT_GT(top, 600) << "a -19 dBFS tone reads about 680 of 1000";
  EXPECT_TRUE(onset);
  EXPECT_TRUE(opened);
  EXPECT_TRUE(closed_again) << "the mouth closes in the silence after";
  EXPECT_EQ(dec->stats().malformed, 0u);
}

TEST(Microphone, WhatItRefusesItSaysWithTheFileOrTheLine) {
  struct Case {
    std::string file;
    const char* says;
  } cases[] = {
      {write_wav("float.wav", 22050, 100, 3, 32), "not PCM (format 3)"},
      {write_wav("eight.wav", 22050, 100, 1, 8), "8-bit samples"},
      {write_wav("fast.wav", 96000, 100), "a sample rate of 96000 Hz"},
      {write_wav("slow.wav", 4000, 100), "a sample rate of 4000 Hz"},
      {(test::temp_dir("wav") / "missing.wav").string(), "missing.wav: cannot open: No such file"},
      {test::write_temp("text.wav", "not a wav at all"), "not a WAV file"},
  };
  for (const Case& c : cases) {
    auto m = MicrophoneSim::make(c.file, "");
    ASSERT_FALSE(m.ok()) << c.file;
    EXPECT_NE(m.error.find(c.file), std::string::npos) << m.error;
    EXPECT_NE(m.error.find(c.says), std::string::npos) << m.error;
  }
  auto m = MicrophoneSim::make("", "");
  ASSERT_TRUE(m.ok());
  auto r = (*m.value)->load_script("0.5 say \"\"\n");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("line 1: say has nothing to say"), std::string::npos) << r.error;
  r = (*m.value)->load_script("\n0.5 shout hello\n");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("line 2: unknown action 'shout'"), std::string::npos) << r.error;
  r = (*m.value)->load_script("1.0 play nowhere.wav\n");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("nowhere.wav: cannot open"), std::string::npos) << r.error;
  // a malformed block is counted and dropped
  DecoderConfig c = (*m.value)->decoder_config();
  auto dec = make_decoder(c, 0);
  const uint8_t odd[3] = {1, 2, 3};
  dec->feed(WireRecord::make(0, WireKind::AudioPcm, odd), [](const Event&) {});
  EXPECT_EQ(dec->stats().malformed, 1u);
}

TEST(Microphone, ItSaysAScriptsLinesAtTheirTimes) {
  if (std::system("command -v espeak-ng >/dev/null 2>&1") != 0) GTEST_SKIP() << "espeak-ng is not installed (Debian package espeak-ng)";
  auto m = MicrophoneSim::make("", "");
  ASSERT_TRUE(m.ok());
  auto r = (*m.value)->load_script("0.5 say \"Hello\"\n2.0 say \"oh\" voice en+f3\n");
  ASSERT_TRUE(r.ok()) << r.error;
  const auto& track = (*m.value)->track();
  auto loud_at = [&](double t0, double t1) {
    double peak = 0;
    for (size_t i = size_t(t0 * MicrophoneSim::kRate); i < size_t(t1 * MicrophoneSim::kRate) && i < track.size(); ++i)
      peak = std::max(peak, std::abs(double(track[i])));
    return peak;
  };
  EXPECT_EQ(loud_at(0, 0.5), 0) << "silence before the first line";
  EXPECT_GT(loud_at(0.5, 1.2), 3000) << "hello";
  EXPECT_GT(loud_at(2.0, 2.6), 3000) << "oh";
}

}  // namespace
}  // namespace mar
