// Canvas frames handed from the frame thread to an output's own thread: a single-producer,
// single-consumer ring of slots made at construction, each a whole frame of premultiplied RGBA8
// with its frame number and show time. The producer copies into a free slot (no allocation, no
// lock, no system call) or, when none is free, drops the frame and counts it — or, lossless (the
// virtual clock), waits for the consumer, which costs wall time only.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <thread>
#include <vector>

namespace mar {

class FrameRing {
 public:
  struct Frame {
    std::vector<uint8_t> rgba;  ///< width * 4 bytes a row, premultiplied
    uint64_t seq = 0;           ///< the show's frame number
    int64_t t_ns = 0;           ///< show time
  };

  FrameRing(int width, int height, size_t slots) : w_(width), h_(height), slots_(slots < 2 ? 2 : slots) {
    for (Frame& f : slots_) f.rgba.resize(size_t(width) * size_t(height) * 4);
  }
  int width() const { return w_; }
  int height() const { return h_; }

  /// Producer: copies a frame (rows `stride` bytes apart). Returns false when the ring was full
  /// and the frame dropped (counted) — or, `wait`, waits for room until `give_up` is set.
  bool push(const uint8_t* rgba, int stride, uint64_t seq, int64_t t_ns, bool wait = false, const std::atomic<bool>* give_up = nullptr) {
    const uint64_t h = head_.load(std::memory_order_relaxed);
    if (h - tail_.load(std::memory_order_acquire) >= slots_.size()) {
      if (!wait) {
        ++full_;
        return false;
      }
      ++waits_;
      const auto start = std::chrono::steady_clock::now();
      while (h - tail_.load(std::memory_order_acquire) >= slots_.size()) {
        if (give_up && give_up->load(std::memory_order_relaxed)) {
          ++full_;
          return false;
        }
        std::this_thread::yield();
      }
      waited_us_ += std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
    }
    Frame& f = slots_[h % slots_.size()];
    const size_t row = size_t(w_) * 4;
    for (int y = 0; y < h_; ++y) std::memcpy(f.rgba.data() + size_t(y) * row, rgba + size_t(y) * size_t(stride), row);
    f.seq = seq;
    f.t_ns = t_ns;
    head_.store(h + 1, std::memory_order_release);
    return true;
  }
  /// Frames dropped because the ring was full (the producer's count).
  uint64_t full() const { return full_; }
  /// Frames that waited for room (lossless pushes), and the wall time they waited in all, µs.
  uint64_t waits() const { return waits_; }
  double waited_us() const { return waited_us_; }

  /// Consumer: frames waiting.
  uint64_t queued() const { return head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_relaxed); }
  /// Consumer: the oldest waiting frame (queued() > 0), then pop().
  const Frame& front() const { return slots_[tail_.load(std::memory_order_relaxed) % slots_.size()]; }
  void pop() { tail_.store(tail_.load(std::memory_order_relaxed) + 1, std::memory_order_release); }
  /// Consumer: skips to the newest waiting frame, returning how many older ones it skipped.
  uint64_t skip_to_newest() {
    const uint64_t n = queued();
    if (n > 1) tail_.store(tail_.load(std::memory_order_relaxed) + n - 1, std::memory_order_release);
    return n > 1 ? n - 1 : 0;
  }
  /// Consumer: drops every waiting frame, returning how many.
  uint64_t clear() {
    const uint64_t n = queued();
    if (n) tail_.store(tail_.load(std::memory_order_relaxed) + n, std::memory_order_release);
    return n;
  }

 private:
  int w_, h_;
  std::vector<Frame> slots_;
  std::atomic<uint64_t> head_{0}, tail_{0};  ///< written by the producer / the consumer
  uint64_t full_ = 0, waits_ = 0;            ///< the producer's
  double waited_us_ = 0;
};

}  // namespace mar
