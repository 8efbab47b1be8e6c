// Single-producer single-consumer ring of trivially copyable items: a helper thread hands
// the frame thread data without a lock or an allocation. Full ring: push() fails.
#pragma once

#include <atomic>
#include <cstddef>

namespace mar {

template <class T, size_t N>
class SpscRing {
  static_assert((N & (N - 1)) == 0, "N must be a power of two");

 public:
  bool push(const T& v) {
    const size_t h = head_.load(std::memory_order_relaxed);
    if (h - tail_.load(std::memory_order_acquire) == N) return false;
    items_[h & (N - 1)] = v;
    head_.store(h + 1, std::memory_order_release);
    return true;
  }
  /// Producer: how many push() calls will succeed now (at least; the consumer may free more).
  size_t room() const { return N - (head_.load(std::memory_order_relaxed) - tail_.load(std::memory_order_acquire)); }
  bool pop(T& v) {
    const size_t t = tail_.load(std::memory_order_relaxed);
    if (t == head_.load(std::memory_order_acquire)) return false;
    v = items_[t & (N - 1)];
    tail_.store(t + 1, std::memory_order_release);
    return true;
  }

 private:
  T items_[N];
  alignas(64) std::atomic<size_t> head_{0};
  alignas(64) std::atomic<size_t> tail_{0};
};

}  // namespace mar
