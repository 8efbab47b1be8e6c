// What a run reports (`--stats`): per-stage times, overruns, iterations, input latency, pose
// quality, and the run_hash, an FNV-1a hash over every frame's deformed vertices (two runs
// that drew the same character frame by frame have the same hash). Adding never allocates.
#pragma once

#include "app/stats.h"
#include "geom/types.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace mar {

class RunHash {
 public:
  void add(const std::vector<Points>& shapes) {
    for (const Points& s : shapes)
      for (const Vec2& v : s) {
        const double xy[2] = {v.x(), v.y()};
        const auto* b = reinterpret_cast<const uint8_t*>(xy);
        for (size_t k = 0; k < sizeof xy; ++k) h_ = (h_ ^ b[k]) * 1099511628211ull;
      }
  }
  uint64_t value() const { return h_; }

 private:
  uint64_t h_ = 1469598103934665603ull;
};

/// The frame's stages, in order (DESIGN: inputs -> map -> poses -> motion -> solve ->
/// render -> present).
enum class Stage : uint8_t { Inputs, Map, Poses, Motion, Solve, Render, Present, Count };
const char* stage_name(Stage s);

struct RunStats {
  Histogram stage[size_t(Stage::Count)];
  Histogram frame, latency;
  Histogram quality;  ///< worst-part distortion per frame, in 0.001 % of the character's height
  long frames = 0, overruns = 0, iter_sum = 0;
  int iter_min = 1 << 30, iter_max = 0;
  RunHash hash;

  /// Ends a frame: its work took `compute_us` of a `budget_us` period at `iterations`.
  void end_frame(double compute_us, double budget_us, int iterations) {
    frame.add(compute_us);
    if (compute_us > budget_us) ++overruns;
    iter_sum += iterations;
    iter_min = std::min(iter_min, iterations);
    iter_max = std::max(iter_max, iterations);
    ++frames;
  }
  double iter_mean() const { return frames ? double(iter_sum) / double(frames) : 0.0; }
};

}  // namespace mar
