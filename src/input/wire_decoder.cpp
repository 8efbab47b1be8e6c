#include "input/wire_decoder.h"

#include <climits>
#include <cstring>

namespace mar {

std::unique_ptr<WireDecoder> WireDecoder::midi(WireKind k, uint16_t source) {
  auto d = std::unique_ptr<WireDecoder>(new WireDecoder());
  d->kind_ = k;
  d->source_ = source;
  if (k == WireKind::UsbMidi)
    d->usb_ = std::make_unique<UsbMidiDecoder>();
  else
    d->stream_ = std::make_unique<MidiStreamDecoder>();
  return d;
}

std::unique_ptr<WireDecoder> WireDecoder::hid(HidDescriptor desc, uint16_t source) {
  auto d = std::unique_ptr<WireDecoder>(new WireDecoder());
  d->kind_ = WireKind::HidReport;
  d->source_ = source;
  d->hid_ = std::move(desc);
  for (const auto& r : d->hid_.reports) d->last_.emplace_back(r.size_bytes(), 0);
  d->seen_.assign(d->hid_.reports.size(), 0);
  return d;
}

std::unique_ptr<WireDecoder> WireDecoder::gpio(GpioLayout layout, uint16_t source) {
  auto d = std::unique_ptr<WireDecoder>(new WireDecoder());
  d->kind_ = WireKind::GpioEdge;
  d->source_ = source;
  d->gpio_ = std::move(layout);
  d->line_role_.assign(256, INT_MIN);
  for (size_t e = 0; e < d->gpio_.encoders.size(); ++e) {
    const auto& enc = d->gpio_.encoders[e];
    d->quad_.emplace_back(enc.steps_per_detent, d->gpio_.debounce_ns);
    d->quad_.back().set_levels(true, true);  // pull-ups: detent rest at A = B = 1
    d->line_role_[size_t(enc.line_a & 0xFF)] = int(e) * 2;
    d->line_role_[size_t(enc.line_b & 0xFF)] = int(e) * 2 + 1;
  }
  for (size_t b = 0; b < d->gpio_.buttons.size(); ++b) d->line_role_[size_t(d->gpio_.buttons[b] & 0xFF)] = -int(b) - 1;
  d->button_level_.assign(d->gpio_.buttons.size(), 1);
  d->button_t_.assign(d->gpio_.buttons.size(), INT64_MIN / 2);
  return d;
}

std::unique_ptr<WireDecoder> WireDecoder::events(uint16_t source) {
  auto d = std::unique_ptr<WireDecoder>(new WireDecoder());
  d->kind_ = WireKind::Event;
  d->source_ = source;
  return d;
}

void WireDecoder::reset() {
  if (usb_) usb_->reset();
  if (stream_) stream_->reset();
  std::fill(seen_.begin(), seen_.end(), 0);
}

void WireDecoder::push(const Event& e) {
  if (n_ < std::size(out_)) out_[n_++] = e;
}

void WireDecoder::decode(const WireRecord& r) {
  if (r.kind != kind_) {
    ++stats_.malformed;
    return;
  }
  switch (kind_) {
    case WireKind::UsbMidi:
    case WireKind::MidiBytes: {
      const uint64_t before = usb_ ? usb_->dropped_bytes() : stream_->stats().dropped_bytes;
      auto on = [&](const MidiMessage& m) {
        Event e;
        if (midi_to_event(m, r.t_ns, source_, e)) push(e);
      };
      if (usb_)
        usb_->feed(r.bytes(), [&](uint8_t, const MidiMessage& m) { on(m); });
      else
        stream_->feed(r.bytes(), on);
      const uint64_t after = usb_ ? usb_->dropped_bytes() : stream_->stats().dropped_bytes;
      if (after != before) ++stats_.malformed;
      break;
    }
    case WireKind::HidReport: {
      const HidReport* rep = hid_.input_for(r.bytes());
      if (!rep || r.size < rep->size_bytes()) {
        ++stats_.malformed;  // unknown report ID or short report: dropped
        return;
      }
      const size_t ri = size_t(rep - hid_.reports.data());
      const std::span<const uint8_t> prev(last_[ri]);
      const bool first = !seen_[ri];
      for (const auto& f : rep->fields) {
        if (f.is_constant() || f.is_array()) continue;
        for (int k = 0; k < f.count; ++k) {
          int32_t v = 0, old = 0;
          if (!f.value(r.bytes(), k, v)) continue;
          f.value(prev, k, old);
          Event e;
          e.t_ns = r.t_ns;
          e.source = source_;
          e.number = f.usages[size_t(k)];
          if (f.is_relative()) {
            if (v == 0) continue;
            e.kind = ControlKind::EncoderDelta;
            e.value = v;
          } else {
            if (!first && v == old) continue;
            e.kind = ControlKind::HidValue;
            e.value = v;
            e.lo = f.logical_min;
            e.hi = f.logical_max;
          }
          push(e);
        }
      }
      std::copy(r.data, r.data + rep->size_bytes(), last_[ri].begin());
      seen_[ri] = 1;
      break;
    }
    case WireKind::Event: {
      if (r.size != sizeof(Event)) {
        ++stats_.malformed;
        return;
      }
      Event e;
      std::memcpy(&e, r.data, sizeof e);
      e.source = source_;
      push(e);
      break;
    }
    case WireKind::GpioEdge: {
      if (r.size < 2) {
        ++stats_.malformed;
        return;
      }
      const int role = line_role_[r.data[0]];
      if (role == INT_MIN) return;  // a line we do not use
      if (role >= 0) {
        quad_[size_t(role / 2)].edge({r.t_ns, uint8_t(role % 2), r.data[1]});
        encoder_events(r.t_ns);
      } else {
        const size_t b = size_t(-role - 1);
        const int level = r.data[1] ? 1 : 0;
        // Lockout debounce: the first edge counts, chatter within the window is ignored.
        if (level != button_level_[b] && r.t_ns - button_t_[b] >= gpio_.debounce_ns) {
          button_level_[b] = level;
          button_t_[b] = r.t_ns;
          Event e;
          e.t_ns = r.t_ns;
          e.source = source_;
          e.kind = ControlKind::Button;
          e.number = uint32_t(b + 1);
          e.value = level == 0;  // active low
          e.hi = 1;
          push(e);
        }
      }
      break;
    }
  }
}

void WireDecoder::encoder_events(int64_t t) {
  for (size_t i = 0; i < quad_.size(); ++i)
    if (int d = quad_[i].take_detents(); d != 0) {
      Event e;
      e.t_ns = t;
      e.source = source_;
      e.kind = ControlKind::EncoderDelta;
      e.number = uint32_t(i + 1);
      e.value = d;
      push(e);
    }
}

void WireDecoder::settle_gpio(int64_t now) {
  if (kind_ != WireKind::GpioEdge || gpio_.debounce_ns == 0) return;
  for (auto& q : quad_) q.settle(now);
  encoder_events(now);
}

}  // namespace mar
