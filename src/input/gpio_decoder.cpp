// GPIO edges -> Events: quadrature encoders (a stable-time filter when debounced) and
// active-low buttons with a lockout debounce.
#include "input/decoder.h"
#include "input/quadrature.h"

#include <climits>

namespace mar {
namespace {

class GpioDecoder final : public Decoder {
 public:
  GpioDecoder(GpioLayout layout, uint16_t source) : Decoder(WireKind::GpioEdge, source), gpio_(std::move(layout)) {
    line_role_.assign(256, INT_MIN);
    for (size_t e = 0; e < gpio_.encoders.size(); ++e) {
      const auto& enc = gpio_.encoders[e];
      quad_.emplace_back(enc.steps_per_detent, gpio_.debounce_ns);
      quad_.back().set_levels(true, true);  // pull-ups: detent rest at A = B = 1
      line_role_[size_t(enc.line_a & 0xFF)] = int(e) * 2;
      line_role_[size_t(enc.line_b & 0xFF)] = int(e) * 2 + 1;
    }
    for (size_t b = 0; b < gpio_.buttons.size(); ++b) line_role_[size_t(gpio_.buttons[b] & 0xFF)] = -int(b) - 1;
    button_level_.assign(gpio_.buttons.size(), 1);
    button_t_.assign(gpio_.buttons.size(), INT64_MIN / 2);
  }

 private:
  void decode(const WireRecord& r, EventSink& out) override {
    if (r.size < 2) {
      malformed();
      return;
    }
    const int role = line_role_[r.data[0]];
    if (role == INT_MIN) return;  // a line we do not use
    if (role >= 0) {
      quad_[size_t(role / 2)].edge({r.t_ns, uint8_t(role % 2), r.data[1]});
      encoder_events(r.t_ns, out);
      return;
    }
    const size_t b = size_t(-role - 1);
    const int level = r.data[1] ? 1 : 0;
    // Lockout debounce: the first edge counts, chatter within the window is ignored.
    if (level != button_level_[b] && elapsed_at_least(r.t_ns, button_t_[b], gpio_.debounce_ns)) {
      button_level_[b] = level;
      button_t_[b] = r.t_ns;
      Event e = event(r.t_ns, ControlKind::Button);
      e.number = uint32_t(b + 1);
      e.value = level == 0;  // active low
      e.hi = 1;
      out.push(e);
    }
  }
  void settle_at(int64_t now, EventSink& out) override {
    if (gpio_.debounce_ns == 0) return;
    for (auto& q : quad_) q.settle(now);
    encoder_events(now, out);
  }
  void encoder_events(int64_t t, EventSink& out) {
    for (size_t i = 0; i < quad_.size(); ++i)
      if (int d = quad_[i].take_detents(); d != 0) {
        Event e = event(t, ControlKind::EncoderDelta);
        e.number = uint32_t(i + 1);
        e.value = d;
        out.push(e);
      }
  }

  GpioLayout gpio_;
  std::vector<QuadratureDecoder> quad_;
  std::vector<int> button_level_;
  std::vector<int64_t> button_t_;
  std::vector<int> line_role_;  ///< per line: encoder*2 + (0|1), or -(button+1), or INT_MIN
};

}  // namespace

std::unique_ptr<Decoder> make_gpio_decoder(GpioLayout layout, uint16_t source) {
  return std::make_unique<GpioDecoder>(std::move(layout), source);
}

}  // namespace mar
