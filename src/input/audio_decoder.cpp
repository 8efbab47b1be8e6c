// Audio PCM blocks (a capture device's or a simulated microphone's) -> a voice's controls
// (input/voice.h), as HidValue events with usages of their own, so bindings treat them as any
// HID control: `level` an absolute value 0..1000 over -60..0 dBFS, each `viseme` a button held
// while that vowel shows, `onset` a button pressed at a syllable's start.
#include "input/decoder.h"
#include "input/voice.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace mar {
namespace {

class AudioDecoder final : public Decoder {
 public:
  AudioDecoder(const DecoderConfig& c, uint16_t source) : Decoder(WireKind::AudioPcm, source), voice_(c.audio_rate) {
    for (size_t k = 0; k < 5; ++k)
      if (c.voice[k][0] > 0 && c.voice[k][1] > 0) voice_.calibrate(Viseme(k + 1), c.voice[k][0], c.voice[k][1]);
  }

 private:
  void decode(const WireRecord& r, EventSink& out) override {
    if (r.size % 2 != 0 || r.size == 0) return malformed();
    int16_t pcm[WireRecord::kMax / 2];
    const size_t n = r.size / 2;
    std::memcpy(pcm, r.data, r.size);
    auto put = [&](uint32_t usage, int32_t value, int32_t hi) {
      Event e = event(r.t_ns, ControlKind::HidValue);
      e.number = usage;
      e.value = value;
      e.lo = 0;
      e.hi = hi;
      out.push(e);
    };
    if (onset_down_) {  // an onset is a press of one analysis frame
      put(voice_usage::kOnset, 0, 1);
      onset_down_ = false;
    }
    voice_.push(std::span<const int16_t>(pcm, n), [&](const VoiceFrame& f) {
      const int32_t level = int32_t(std::lround(std::clamp((f.level_db + 60) / 60, 0.0, 1.0) * 1000));
      if (level != level_) {
        put(voice_usage::kLevel, level, 1000);
        level_ = level;
      }
      if (f.viseme != shown_) {
        put(voice_usage::viseme(shown_), 0, 1);
        put(voice_usage::viseme(f.viseme), 1, 1);
        shown_ = f.viseme;
      }
      if (f.onset && !onset_down_) {
        put(voice_usage::kOnset, 1, 1);
        onset_down_ = true;
      }
    });
  }

  VoiceAnalyzer voice_;
  int32_t level_ = -1;
  Viseme shown_ = Viseme::Closed;
  bool onset_down_ = false;
};

}  // namespace

std::unique_ptr<Decoder> make_audio_decoder(const DecoderConfig& c, uint16_t source) {
  if (c.audio_rate < 4000 || c.audio_rate > 192000) return nullptr;
  return std::make_unique<AudioDecoder>(c, source);
}

WireRecord audio_record(int64_t t, std::span<const int16_t> pcm, uint16_t source) {
  const size_t n = std::min(pcm.size(), WireRecord::kMax / 2);
  return WireRecord::make(t, WireKind::AudioPcm, std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(pcm.data()), n * 2), source);
}

}  // namespace mar
