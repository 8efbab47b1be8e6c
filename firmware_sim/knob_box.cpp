#include "firmware_sim/knob_box.h"

#include <algorithm>
#include <cmath>

namespace mar {
namespace {
constexpr int kSeq[4][2] = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};  // (A, B) by Gray index
}

void KnobBoxSim::edge(int64_t t, int line, int level, int64_t room_ns) {
  const uint8_t e[2] = {uint8_t(line), uint8_t(level)};
  emit(t, e);
  if (bounce_ms_ <= 0) return;
  std::uniform_real_distribution<double> len_ms(0.2, std::max(0.2, bounce_ms_));
  const int64_t len = std::min(to_ns(len_ms(rng_) * 1e-3), room_ns / 2);
  if (len < 20'000) return;
  const int toggles = 2 * (1 + int(rng_() % 3));
  for (int k = 1; k <= toggles; ++k) {
    const uint8_t b[2] = {uint8_t(line), uint8_t(k % 2 ? !level : level)};
    emit(t + len * k / toggles, b);
  }
}

void KnobBoxSim::turn(int enc, double t_s, int detents, double dur_s) {
  if (enc < 1 || enc > kEncoders || detents == 0) return;
  const int steps = 4 * std::abs(detents);
  const int64_t t0 = to_ns(t_s), span = to_ns(std::max(dur_s, 0.0));
  const int64_t gap = std::max<int64_t>(span / steps, 1);
  int& ph = phase_[enc - 1];
  for (int s = 0; s < steps && !too_many_; ++s) {
    const int next = (ph + (detents > 0 ? 1 : 3)) % 4;
    const int which = kSeq[ph][0] != kSeq[next][0] ? 0 : 1;
    edge(t0 + s * gap, which == 0 ? line_a(enc) : line_b(enc), kSeq[next][which], gap);
    ph = next;
  }
}

void KnobBoxSim::press(int enc, double t_s, double hold_s) {
  if (enc < 1 || enc > kEncoders) return;
  const int64_t t0 = to_ns(t_s), hold = to_ns(std::max(hold_s, 0.005));
  edge(t0, line_button(enc), 0, hold);
  edge(t0 + hold, line_button(enc), 1, hold);
}

Result<bool> KnobBoxSim::action(double t, const std::vector<std::string>& w) {
  using R = Result<bool>;
  double enc = 0;
  if (w.size() < 2 || !parse_number(w[1], enc) || enc < 1 || enc > kEncoders || enc != std::floor(enc))
    return R::failure("expected 'turn ENCODER DETENTS [over S]' or 'press ENCODER [for S]' with ENCODER 1-4");
  if (w[0] == "turn") {
    double n = 0, dur = 0;
    if (w.size() < 3 || !parse_number(w[2], n) || n != std::floor(n) || std::abs(n) > 1e6)
      return R::failure("turn needs a whole number of detents");
    if (w.size() == 5 && w[3] == "over" && parse_number(w[4], dur) && dur >= 0) {
    } else if (w.size() != 3) {
      return R::failure("expected 'turn ENCODER DETENTS [over SECONDS]'");
    }
    turn(int(enc), t, int(n), dur);
    return R::success(true);
  }
  if (w[0] == "press") {
    double hold = 0.1;
    if (w.size() == 4 && w[2] == "for" && parse_number(w[3], hold) && hold >= 0) {
    } else if (w.size() != 2) {
      return R::failure("expected 'press ENCODER [for SECONDS]'");
    }
    press(int(enc), t, hold);
    return R::success(true);
  }
  return R::failure("unknown action '" + w[0] + "' (turn, press)");
}

}  // namespace mar
