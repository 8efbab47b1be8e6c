// HID input reports -> Events, by the device's report descriptor: absolute fields become
// HidValue events when they change (all of them on a report's first appearance), relative
// fields EncoderDelta events when non-zero.
#include "input/decoder.h"

#include <algorithm>

namespace mar {
namespace {

class HidDecoder final : public Decoder {
 public:
  HidDecoder(HidDescriptor d, uint16_t source) : Decoder(WireKind::HidReport, source), hid_(std::move(d)) {
    for (const auto& r : hid_.reports) last_.emplace_back(r.size_bytes(), 0);
    seen_.assign(hid_.reports.size(), 0);
  }

 private:
  void decode(const WireRecord& r, EventSink& out) override {
    const HidReport* rep = hid_.input_for(r.bytes());
    if (!rep || r.size < rep->size_bytes()) {
      malformed();  // unknown report ID or short report: dropped
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
        Event e = event(r.t_ns, ControlKind::HidValue);
        e.number = f.usages[size_t(k)];
        if (f.is_relative()) {
          if (v == 0) continue;
          e.kind = ControlKind::EncoderDelta;
          e.value = v;
        } else {
          if (!first && v == old) continue;
          e.value = v;
          e.lo = f.logical_min;
          e.hi = f.logical_max;
        }
        out.push(e);
      }
    }
    std::copy(r.data, r.data + rep->size_bytes(), last_[ri].begin());
    seen_[ri] = 1;
  }

  HidDescriptor hid_;
  std::vector<std::vector<uint8_t>> last_;  ///< previous report per descriptor report
  std::vector<char> seen_;
};

}  // namespace

std::unique_ptr<Decoder> make_hid_decoder(HidDescriptor d, uint16_t source) {
  return std::make_unique<HidDecoder>(std::move(d), source);
}

}  // namespace mar
