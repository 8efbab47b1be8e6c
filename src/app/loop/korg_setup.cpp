#include "app/loop/korg_setup.h"

namespace mar {

namespace {
constexpr int kEcho = 0x4D;  // (any 7-bit value: the reply repeats it)
}

void KorgLedSetup::send(uint16_t device, LedSink& io, size_t n, Phase next, int64_t t_ns) {
  // A message the backend could not take now (its ring full) is tried again next frame.
  phase_ = next;
  deadline_ = t_ns + kTimeout;
  pending_ = n;
  if (pending_ && io.send(device, std::span<const uint8_t>(out_.data(), pending_))) pending_ = 0;
}

bool KorgLedSetup::step(int64_t t_ns, uint16_t device, LedSink& io) {
  switch (phase_) {
    case Phase::Start:
      io.last_sysex(device, seen_);  // (only answers from now on count)
      told_ = false;
      send(device, io, korg::search_request(kEcho, out_), Phase::Searching, t_ns);
      return true;
    case Phase::Searching:
    case Phase::Reading:
    case Phase::Loading: break;
    default: return false;
  }
  if (pending_ && io.send(device, std::span<const uint8_t>(out_.data(), pending_))) pending_ = 0;
  uint64_t count = 0;
  const std::span<const uint8_t> m = io.last_sysex(device, count);
  if (count != seen_) {
    seen_ = count;
    const korg::Message a = korg::parse(m, phase_ == Phase::Reading ? &scene_ : nullptr);
    if (phase_ == Phase::Searching && a.kind == korg::Kind::SearchReply && a.echo == kEcho && a.family == korg::kFamily) {
      channel_ = a.channel;
      send(device, io, korg::dump_request(channel_, out_), Phase::Reading, t_ns);
    } else if (phase_ == Phase::Reading && a.kind == korg::Kind::SceneData && a.channel == channel_) {
      if (scene_[korg::kLedModeAt] == 1) {
        phase_ = Phase::Already;
        return false;
      }
      scene_[korg::kLedModeAt] = 1;
      send(device, io, korg::scene_data(channel_, scene_, out_), Phase::Loading, t_ns);
    } else if (phase_ == Phase::Loading && a.channel == channel_ && (a.kind == korg::Kind::Ack || a.kind == korg::Kind::Nak)) {
      phase_ = a.kind == korg::Kind::Ack ? Phase::Switched : Phase::Refused;
      return false;
    }
  }
  if (t_ns >= deadline_) {
    phase_ = Phase::NoAnswer;
    return false;
  }
  return true;
}

const char* KorgLedSetup::take_news() {
  if (told_) return nullptr;
  const char* s = nullptr;
  switch (phase_) {
    case Phase::Switched: s = "LED mode set to External for this session (its stored scene is unchanged): its lights show the show"; break;
    case Phase::Already: s = "its scene's LED mode is External already: its lights show the show"; break;
    case Phase::NoAnswer:
      s = "did not answer Korg's scene requests within a second: its lights follow its buttons unless its LED mode is "
          "External (Korg Kontrol Editor: Common > LED Mode)";
      break;
    case Phase::Refused: s = "refused its scene with the External LED mode (NAK): its lights follow its buttons"; break;
    default: return nullptr;
  }
  told_ = true;
  return s;
}

}  // namespace mar
