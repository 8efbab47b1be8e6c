// The budget governor: one fewer solver iteration (never below the floor) when the last
// frame used more than 80% of the frame budget, one more (never above what the show asks
// for) below 40%. Replays use the recorded counts instead.
#pragma once

namespace mar {

class Governor {
 public:
  Governor(int start, int floor) : iterations_(start), floor_(floor) {}
  /// The iteration count for this frame: `want` is what the show asks for now,
  /// `last_ms` what the last frame's work took, `budget_ms` the frame period.
  int next(int want, double last_ms, double budget_ms) {
    if (iterations_ > want) iterations_ = want;
    if (last_ms > 0.8 * budget_ms && iterations_ > floor_) {
      --iterations_;
      ++reductions_;
    } else if (last_ms < 0.4 * budget_ms && iterations_ < want) {
      ++iterations_;
    }
    return iterations_;
  }
  /// A replayed frame's count.
  void force(int iterations) { iterations_ = iterations; }
  int iterations() const { return iterations_; }
  long reductions() const { return reductions_; }

 private:
  int iterations_, floor_;
  long reductions_ = 0;
};

}  // namespace mar
