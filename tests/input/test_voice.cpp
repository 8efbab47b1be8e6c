// A voice's visemes from PCM, measured on espeak-ng's sustained vowels in three voices (a man's
// British and American English and a woman's): each voice calibrated on its vowels at one pitch,
// then heard at two other pitches and speeds. Goals: the right viseme on >= 85% of voiced
// frames, closed on >= 99% of silent ones, the mouth open within 20 ms of the sound's onset.
// The figures are printed for README. Without espeak-ng (Debian package espeak-ng) it skips.
#include "input/voice.h"
#include "voice_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>

namespace mar {
namespace {

using test::have_espeak;
using test::speak;

const std::pair<Viseme, const char*> kVowels[] = {
    {Viseme::A, "a:"}, {Viseme::I, "i:"}, {Viseme::U, "u:"}, {Viseme::E, "e:"}, {Viseme::O, "o:"}};

TEST(Voice, VisemesOfThreeVoicesAfterCalibration) {
  if (!have_espeak()) GTEST_SKIP() << "espeak-ng is not installed (Debian package espeak-ng): no voices to measure";
  long voiced_all = 0, right_all = 0, silent_all = 0, closed_all = 0;
  for (const char* voice : {"en", "en-us", "en+f3"}) {
    // Calibration: the performer says a, i, u, e, o once.
    VoiceOptions o;
    int rate = 0;
    std::map<Viseme, std::pair<double, double>> cal;
    for (const auto& [v, ph] : kVowels) {
      auto pcm = speak(voice, ph, 50, 80, rate);
      ASSERT_FALSE(pcm.empty()) << voice << " " << ph;
      double f1 = 0, f2 = 0;
      ASSERT_TRUE(VoiceAnalyzer::measure_vowel(rate, pcm, f1, f2, o)) << voice << " " << ph;
      cal[v] = {f1, f2};
    }
    long voiced = 0, right = 0, silent = 0, closed = 0, right_default = 0;
    for (const auto& [pitch, speed] : {std::pair{35, 100}, std::pair{65, 130}}) {
      for (const auto& [v, ph] : kVowels) {
        const Viseme vowel = v;  // clang 14 cannot capture a structured binding
        auto pcm = speak(voice, ph, pitch, speed, rate);
        VoiceAnalyzer a(rate, o), uncalibrated(rate, o);
        for (const auto& [cv, f] : cal) a.calibrate(cv, f.first, f.second);
        std::vector<Viseme> plain;  // the default templates' visemes, frame by frame
        uncalibrated.push(pcm, [&](const VoiceFrame& f) { plain.push_back(f.viseme); });
        // each frame's raw level, to tell voiced frames (clearly above the gate) from silent ones
        // (silent for the last 200 ms, past the release)
        const int hop = int(std::lround(o.hop_s * rate)), win = int(std::lround(o.frame_s * rate));
        long frame = 0, quiet_hops = 0;
        a.push(pcm, [&](const VoiceFrame& f) {
          const size_t end = size_t((frame + 1) * hop);
          double s2 = 0;
          for (size_t k = end > size_t(win) ? end - size_t(win) : 0; k < end && k < pcm.size(); ++k) s2 += double(pcm[k]) * pcm[k];
          const double db = 20 * std::log10(std::max(1e-6, std::sqrt(s2 / win) / 32768));
          quiet_hops = db < -60 ? quiet_hops + 1 : 0;
          if (db > o.gate_db + 6) {
            ++voiced;
            right += f.viseme == vowel;
            right_default += size_t(frame) < plain.size() && plain[size_t(frame)] == vowel;
          } else if (quiet_hops * o.hop_s >= 0.2) {
            ++silent;
            closed += f.viseme == Viseme::Closed;
          }
          ++frame;
        });
      }
    }
    std::printf("voice %-6s: the right viseme on %5.1f%% of %ld voiced frames (%.1f%% with the default templates), closed on %5.1f%% of %ld silent ones\n",
                voice, 100.0 * right / std::max(1L, voiced), voiced, 100.0 * right_default / std::max(1L, voiced), 100.0 * closed / std::max(1L, silent),
                silent);
    EXPECT_GE(double(right) / voiced, 0.85) << voice;
    EXPECT_GE(double(closed) / std::max(1L, silent), 0.99) << voice;
    voiced_all += voiced;
    right_all += right;
    silent_all += silent;
    closed_all += closed;
  }
  std::printf("all voices: %.1f%% right of %ld voiced frames, %.1f%% closed of %ld silent\n", 100.0 * right_all / voiced_all, voiced_all,
              100.0 * closed_all / std::max(1L, silent_all), silent_all);
}

TEST(Voice, TheMouthOpensWithinTwentyMillisecondsOfASound) {
  if (!have_espeak()) GTEST_SKIP() << "espeak-ng is not installed (Debian package espeak-ng)";
  int rate = 0;
  auto said = speak("en", "a:", 50, 120, rate);
  ASSERT_FALSE(said.empty());
  std::vector<int16_t> pcm(size_t(rate) * 3 / 10, 0);  // 0.3 s of silence, then the vowel
  pcm.insert(pcm.end(), said.begin(), said.end());
  // the sound's onset: the end of the first 5 ms whose RMS is above the gate
  const VoiceOptions o;
  const size_t block = size_t(rate / 200);
  size_t onset = 0;
  for (size_t b = 0; b + block <= pcm.size(); b += block) {
    double s2 = 0;
    for (size_t k = b; k < b + block; ++k) s2 += double(pcm[k]) * pcm[k];
    if (20 * std::log10(std::max(1e-9, std::sqrt(s2 / double(block)) / 32768)) > o.gate_db) {
      onset = b + block;
      break;
    }
  }
  ASSERT_GT(onset, 0u);
  VoiceAnalyzer a(rate, o);
  double opened = -1;
  bool onset_seen = false;
  a.push(pcm, [&](const VoiceFrame& f) {
    if (opened < 0 && f.viseme != Viseme::Closed) opened = f.t;
    onset_seen = onset_seen || f.onset;
  });
  const double latency = opened - double(onset) / rate;
  std::printf("sound onset to an open mouth: %.1f ms\n", 1000 * latency);
  EXPECT_GE(latency, 0.0);
  EXPECT_LE(latency, 0.020);
  EXPECT_TRUE(onset_seen) << "an onset";
}

TEST(Voice, SilenceIsClosedAndNoiseFloorsStayClosed) {
  for (int rate : {16000, 22050, 44100, 48000}) {
    VoiceAnalyzer a(rate);
    std::vector<int16_t> quiet(size_t(rate), 0);
    for (size_t i = 0; i < quiet.size(); ++i) quiet[i] = int16_t((i * 7919) % 41) - 20;  // a -65 dBFS hiss
    long open = 0, frames = 0;
    a.push(quiet, [&](const VoiceFrame& f) {
      ++frames;
      open += f.viseme != Viseme::Closed;
    });
    EXPECT_EQ(open, 0) << rate;
    EXPECT_GT(frames, 90) << rate;
  }
}

}  // namespace
}  // namespace mar
