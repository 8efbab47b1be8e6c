#include "input/quadrature.h"

#include "input/event.h"

namespace mar {
namespace {
// Gray index of state (A << 1 | B): 00 -> 0, 01 -> 1, 11 -> 2, 10 -> 3.
constexpr int kGray[4] = {0, 1, 3, 2};
}  // namespace

QuadratureDecoder::QuadratureDecoder(int steps_per_detent, int64_t debounce_ns)
    : steps_per_detent_(steps_per_detent < 1 ? 1 : steps_per_detent), debounce_ns_(debounce_ns < 0 ? 0 : debounce_ns) {}

void QuadratureDecoder::set_levels(bool a, bool b) {
  level_[0] = raw_[0] = a;
  level_[1] = raw_[1] = b;
}

int QuadratureDecoder::apply(int line, bool level, int64_t t) {
  if (level_[line] == level) return 0;
  const int before = kGray[(level_[0] ? 2 : 0) | (level_[1] ? 1 : 0)];
  level_[line] = level;
  const int after = kGray[(level_[0] ? 2 : 0) | (level_[1] ? 1 : 0)];
  const int d = (after - before + 4) % 4;
  if (d == 2) {  // cannot happen with one line changing; kept for safety
    ++invalid_;
    return 0;
  }
  const int step = d == 1 ? 1 : -1;
  position_ += step;
  detent_acc_ += step;
  ++transitions_;
  last_change_ns_ = t;
  return step;
}

int QuadratureDecoder::settle(int64_t now_ns) {
  int sum = 0;
  for (int line = 0; line < 2; ++line)
    if (raw_[line] != level_[line] && elapsed_at_least(now_ns, raw_t_[line], debounce_ns_)) sum += apply(line, raw_[line], raw_t_[line]);
  return sum;
}

int QuadratureDecoder::edge(const LineEdge& e) {
  const int line = e.line & 1;
  if (debounce_ns_ == 0) return apply(line, e.level != 0, e.t_ns);
  int sum = settle(e.t_ns);
  raw_[line] = e.level != 0;
  raw_t_[line] = e.t_ns;
  return sum;
}

int QuadratureDecoder::take_detents() {
  const int64_t n = detent_acc_ / steps_per_detent_;  // truncates toward zero
  detent_acc_ -= n * steps_per_detent_;
  return int(n);
}

}  // namespace mar
