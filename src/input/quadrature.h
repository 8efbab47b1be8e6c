// Quadrature (incremental encoder) decoding with the standard 4x state table.
//
// Lines A and B each give an edge stream (kernel timestamps from a GPIO chip, or a
// logic capture); the decoder takes the two streams merged by timestamp. Gray sequence
// 00 -> 01 -> 11 -> 10 (written AB; B changes first) counts +1 per quarter step. A
// mechanical detent is `steps_per_detent` quarter steps; detents are whole steps of an
// accumulator, so contact bounce that returns to the same level before the other line
// moves nets to zero. An optional stable-time filter (debounce) accepts a line's new
// level only after it held for the given time; it is applied when a later edge or a
// `settle(now)` call shows the level held.
#pragma once

#include <cstdint>
#include <span>

namespace mar {

struct LineEdge {
  int64_t t_ns = 0;
  uint8_t line = 0;   ///< 0 = A, 1 = B (encoder-local numbering)
  uint8_t level = 0;  ///< level after the edge
};

class QuadratureDecoder {
 public:
  explicit QuadratureDecoder(int steps_per_detent = 4, int64_t debounce_ns = 0);
  /// Sets the line levels without counting (initial state from the device).
  void set_levels(bool a, bool b);
  /// Feeds one edge (edges must come in timestamp order). Returns the quarter-step change
  /// the edge caused now (-1, 0, +1; with a debounce, a change may be applied later).
  int edge(const LineEdge& e);
  /// Applies pending levels that have been stable for the debounce time at `now_ns`.
  int settle(int64_t now_ns);
  /// Quarter steps since start (signed) and transitions counted (unsigned).
  int64_t position() const { return position_; }
  uint64_t quarter_steps() const { return transitions_; }
  uint64_t invalid() const { return invalid_; }  ///< both lines changed at once (a missed edge)
  /// Whole detents since the last call (signed); the remainder is kept.
  int take_detents();
  int64_t last_change_ns() const { return last_change_ns_; }

 private:
  int apply(int line, bool level, int64_t t);
  int steps_per_detent_;
  int64_t debounce_ns_;
  bool level_[2] = {false, false};
  bool raw_[2] = {false, false};
  int64_t raw_t_[2] = {0, 0};
  int64_t position_ = 0, detent_acc_ = 0, last_change_ns_ = 0;
  uint64_t transitions_ = 0, invalid_ = 0;
};

/// Calls `on(const LineEdge&)` for the edges of two per-line streams in timestamp order
/// (A first on equal times); `a` edges get line 0, `b` edges line 1.
template <class F>
void merge_line_edges(std::span<const LineEdge> a, std::span<const LineEdge> b, F&& on) {
  size_t i = 0, j = 0;
  while (i < a.size() || j < b.size()) {
    if (j >= b.size() || (i < a.size() && a[i].t_ns <= b[j].t_ns)) {
      LineEdge e = a[i++];
      e.line = 0;
      on(static_cast<const LineEdge&>(e));
    } else {
      LineEdge e = b[j++];
      e.line = 1;
      on(static_cast<const LineEdge&>(e));
    }
  }
}

}  // namespace mar
