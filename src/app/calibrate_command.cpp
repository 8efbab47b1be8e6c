// `marionette calibrate VOWELS.wav`: a voice's own vowel templates, measured from a recording
// of the performer saying a, i, u, e, o in that order with a pause between each: the table a
// voice device's `calibrate` key takes, printed to paste into the show.
#include "app/commands.h"
#include "firmware_sim/microphone.h"
#include "input/voice.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <vector>

namespace mar {

int cmd_calibrate(const CalibrateArgs& a) {
  int rate = 0;
  auto pcm = read_wav(a.wav, rate);
  if (!pcm.ok()) {
    std::cerr << "error: " << pcm.error << "\n";
    return kExitBadInput;
  }
  // The stretches of voice: analysis frames clearly above the gate, at least 120 ms of them,
  // apart by at least 150 ms below it.
  const VoiceOptions o;
  VoiceAnalyzer an(rate, o);
  struct Stretch {
    double from = 0, to = 0;
  };
  std::vector<Stretch> voiced;
  bool in = false;
  double last_loud = -1;
  an.push(*pcm.value, [&](const VoiceFrame& f) {
    const bool loud = f.level_db > o.gate_db + 6;
    if (loud) {
      if (!in && (voiced.empty() || f.t - last_loud > 0.15)) voiced.push_back({f.t - o.frame_s, f.t});
      in = true;
      last_loud = f.t;
      voiced.back().to = f.t;
    } else {
      in = false;
    }
  });
  std::erase_if(voiced, [](const Stretch& s) { return s.to - s.from < 0.12; });
  if (voiced.size() != 5) {
    std::cerr << "error: " << a.wav << ": " << voiced.size()
              << " stretches of voice; record a, i, u, e, o (as in father, see, moon, bed, go) in that order, "
                 "each held about half a second, with a pause between\n";
    return kExitBadInput;
  }
  const char* names[] = {"a", "i", "u", "e", "o"};
  std::string table = "calibrate = { ";
  for (size_t k = 0; k < 5; ++k) {
    const size_t from = size_t(std::max(0.0, voiced[k].from) * rate), to = std::min(pcm.value->size(), size_t(voiced[k].to * rate));
    double f1 = 0, f2 = 0;
    if (to <= from || !VoiceAnalyzer::measure_vowel(rate, std::span<const int16_t>(pcm.value->data() + from, to - from), f1, f2, o)) {
      std::cerr << "error: " << a.wav << ": no formants heard in the " << names[k] << " (" << voiced[k].from << " s to "
                << voiced[k].to << " s)\n";
      return kExitBadInput;
    }
    char item[64];
    std::snprintf(item, sizeof item, "%s%s = [%.0f, %.0f]", k ? ", " : "", names[k], f1, f2);
    table += item;
  }
  table += " }";
  std::cout << "# " << a.wav << ": a, i, u, e, o measured; put this line in the voice's [[device]] table\n" << table << "\n";
  return kExitOk;
}

}  // namespace mar
