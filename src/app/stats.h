// Fixed-memory timing statistics: a 1 us histogram up to 200 ms (values above land in the
// last bin, the maximum is kept exactly). Adding a sample never allocates.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace mar {

class Histogram {
 public:
  Histogram() : bins_(200'001, 0) {}
  void add(double us) {
    if (!(us >= 0)) us = 0;
    ++bins_[size_t(std::min(us, 2e5))];
    max_ = std::max(max_, us);
    ++n_;
  }
  uint64_t count() const { return n_; }
  double max() const { return max_; }
  /// Smallest bin value with at least q of the samples at or below it (q in 0..1).
  double quantile(double q) const {
    if (n_ == 0) return 0;
    const uint64_t want = std::max<uint64_t>(1, uint64_t(q * double(n_) + 0.999999));
    uint64_t seen = 0;
    for (size_t i = 0; i < bins_.size(); ++i) {
      seen += bins_[i];
      if (seen >= want) return std::min(double(i) + 0.5, max_);
    }
    return max_;
  }
  void clear() {
    std::fill(bins_.begin(), bins_.end(), 0);
    n_ = 0;
    max_ = 0;
  }

 private:
  std::vector<uint32_t> bins_;
  uint64_t n_ = 0;
  double max_ = 0;
};

}  // namespace mar
