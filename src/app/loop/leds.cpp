#include "app/loop/leds.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <climits>
#include <cmath>

namespace mar {

void LedFeedback::prepare(const ShowConfig& show, const Mapping& m) {
  lights_.clear();
  inits_.clear();
  for (size_t d = 0; d < show.devices.size(); ++d)
    if (!show.devices[d].init.empty() || show.devices[d].korg_external_leds) {
      Init in;
      in.device = uint16_t(d);
      in.messages = show.devices[d].init;
      in.korg = show.devices[d].korg_external_leds;
      inits_.push_back(std::move(in));
    }
  waiting_.assign(show.devices.size(), 0);
  for (size_t i = 0; i < m.binding_count(); ++i) {
    const Binding& b = m.binding(i);
    if (b.led == -2 || b.control.device >= show.devices.size()) continue;
    const ShowDevice& d = show.devices[b.control.device];
    const DeviceLed* led = nullptr;
    for (const DeviceLed& l : d.leds)
      if (l.control == b.control.text || l.name == b.control.text) led = &l;
    if (!led) continue;
    Light L;
    L.device = b.control.device;
    L.binding = int(i);
    L.index = b.index;
    L.member = b.member;
    switch (b.target) {
      case TargetKind::Trigger: L.source = Source::Trigger; break;
      case TargetKind::Swap: L.source = Source::Swap; break;
      case TargetKind::Pose: L.source = Source::Pose; break;
      case TargetKind::HandleX:
      case TargetKind::HandleY:
      case TargetKind::Rotate:
      case TargetKind::Setting:
        if (!led->ring) continue;
        L.source = Source::Ring;
        break;
      default: continue;  // grabs, recalls, points: no state a light could show
    }
    if ((L.source == Source::Ring) != led->ring) continue;
    // One light per message: the first binding on it drives it.
    const bool taken = std::any_of(lights_.begin(), lights_.end(), [&](const Light& o) {
      return o.device == L.device && o.size == led->bytes.size() && std::equal(led->bytes.begin(), led->bytes.end(), o.bytes.begin());
    });
    if (taken) continue;
    L.size = uint8_t(std::min(led->bytes.size(), L.bytes.size()));
    std::copy_n(led->bytes.begin(), L.size, L.bytes.begin());
    L.value_at = uint8_t(led->value_at);
    L.on = b.led >= 0 ? b.led : led->on;
    L.off = led->off;
    L.lo = led->lo;
    L.hi = led->hi;
    lights_.push_back(L);
  }
}

void LedFeedback::frame(int64_t t_ns, const Mapping& m, std::span<const int> swap_members, std::span<const char> triggers,
                        std::span<const DeviceState> states, LedSink& out) {
  auto connected = [&](uint16_t d) { return d >= states.size() || states[d] == DeviceState::Connected; };
  // A device that (re)connects: its init messages, then every light again.
  for (Init& in : inits_) {
    if (!connected(in.device)) {
      in.sent = in.done = false;
      in.setup.reset();
      continue;
    }
    if (in.done) continue;
    if (!in.sent) {
      for (const auto& msg : in.messages) {
        if (out.send(in.device, msg)) ++init_sent_;
        else ++failed_;
      }
      in.sent = true;
    }
    waiting_[in.device] = in.korg && in.setup.step(t_ns, in.device, out);
    if (waiting_[in.device]) continue;
    in.done = true;
    for (Light& L : lights_)
      if (L.device == in.device) L.sent = -1;
  }
  int budget = kPerFrame;
  for (Light& L : lights_) {
    if (!connected(L.device) || waiting_[L.device]) {
      L.sent = -1;  // (sent again when it is back, or set up)
      continue;
    }
    switch (L.source) {
      case Source::Trigger: L.want = size_t(L.index) < triggers.size() && triggers[size_t(L.index)] ? L.on : L.off; break;
      case Source::Swap:
        L.want = size_t(L.index) < swap_members.size() && swap_members[size_t(L.index)] == L.member ? L.on : L.off;
        break;
      case Source::Pose: L.want = m.current_pose() == L.index ? L.on : L.off; break;
      case Source::Ring: {
        const Binding& b = m.binding(size_t(L.binding));
        const double v = m.binding_value(size_t(L.binding));
        const double span = b.tf.hi - b.tf.lo;
        const double n = std::isfinite(v) && span != 0 ? std::clamp((v - b.tf.lo) / span, 0.0, 1.0) : 0.0;
        L.want = int(std::lround(L.lo + n * (L.hi - L.lo)));
        break;
      }
    }
    if (L.want == L.sent) continue;
    if (t_ns - L.sent_at < kMinInterval || budget == 0) {
      ++deferred_;
      continue;
    }
    L.bytes[L.value_at] = uint8_t(L.want & 0x7F);
    if (out.send(L.device, std::span<const uint8_t>(L.bytes.data(), L.size))) {
      ++sent_;
    } else {
      ++failed_;
    }
    L.sent = L.want;  // (a message the device would not take is not retried every frame)
    L.sent_at = t_ns;
    --budget;
  }
}

bool LedFeedback::echo(const Event& e, int64_t t_ns) {
  int status = 0;
  if (e.kind == ControlKind::MidiCC) status = 0xB0;
  else if (e.kind == ControlKind::MidiNoteOn) status = 0x90;
  else if (e.kind == ControlKind::MidiNoteOff) status = 0x80;
  else return false;
  for (const Light& L : lights_) {
    if (L.device != e.source || L.size != 3 || L.sent < 0 || t_ns - L.sent_at > kEchoWindow) continue;
    const int ls = L.bytes[0] & 0xF0, lch = L.bytes[0] & 0x0F;
    const bool same_kind = ls == status || (ls == 0x90 && status == 0x80 && L.sent == 0);
    if (same_kind && lch == e.channel && L.bytes[1] == e.number && (status == 0x80 ? L.sent == 0 : L.sent == e.value)) {
      ++echoes_;
      return true;
    }
  }
  return false;
}

bool LedFeedback::take_news(uint16_t& device, const char*& text) {
  for (Init& in : inits_)
    if (in.korg && (text = in.setup.take_news())) {
      device = in.device;
      return true;
    }
  return false;
}

void LedFeedback::add_stats(nlohmann::json& stats) const {
  stats["leds"] = {{"lights", lights_.size()}, {"sent", sent_}, {"deferred", deferred_}, {"failed", failed_},
                   {"echoes_dropped", echoes_}, {"init_messages", init_sent_}};
  for (const Init& in : inits_) {
    if (!in.korg) continue;
    static const char* const names[] = {"start", "searching", "reading", "loading", "switched", "already", "no answer", "refused"};
    stats["leds"]["korg_led_mode"] = names[int(in.setup.phase())];
  }
}

}  // namespace mar
