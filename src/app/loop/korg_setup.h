// Putting a Korg nanoKONTROL2 in its External LED mode, so its lights show the show: on
// connecting, the frame asks the unit who it is (search device: its global channel), reads its
// current scene, and when the LED mode is not External already, sends the scene back with it
// set, and waits for the ACK (input/korg_scene.h). Nothing is written to the unit's memory:
// unplugged, it is as its owner left it. Each step waits at most a second for its answer; a
// unit that does not answer (an older firmware, a port that drops SysEx) is said once and its
// lights are sent anyway. One step per frame, allocation-free: the frame only hands messages to
// the backend and reads the last SysEx its decoder kept.
#pragma once

#include "app/loop/led_sink.h"
#include "input/korg_scene.h"

#include <array>
#include <cstdint>

namespace mar {

class KorgLedSetup {
 public:
  enum class Phase : uint8_t { Start, Searching, Reading, Loading, Switched, Already, NoAnswer, Refused };
  static constexpr int64_t kTimeout = 1'000'000'000;
  /// From the start (the device connected again).
  void reset() { phase_ = Phase::Start; }
  /// One frame at show time `t_ns` for show device `device`; true while its lights must wait.
  bool step(int64_t t_ns, uint16_t device, LedSink& io);
  Phase phase() const { return phase_; }
  /// A sentence on how it ended, once (nullptr before, and after it was taken).
  const char* take_news();

 private:
  void send(uint16_t device, LedSink& io, size_t n, Phase next, int64_t t_ns);
  Phase phase_ = Phase::Start;
  bool told_ = false;
  int channel_ = 0;
  int64_t deadline_ = 0;
  uint64_t seen_ = 0;
  size_t pending_ = 0;  ///< bytes of out_ the backend has not taken yet
  std::array<uint8_t, korg::kSceneMessage> out_{};
  korg::Scene scene_{};
};

}  // namespace mar
