// A pool of threads started once (at load) that runs a frame's independent items — a cast's
// actors' solves — on the machine's cores. run() hands out items through an atomic counter;
// the caller takes items too, and returns when every item is done and every helper is back
// waiting. Nothing in run() allocates or takes a lock: helpers sleep on an atomic (a futex)
// between frames, as the rasterizer's helper does. Which thread runs an item never changes
// what it computes, so the results are the same with one thread or many.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <thread>
#include <vector>

namespace mar {

class WorkerPool {
 public:
  /// `threads` in all, the caller's included (1: no helper; run() is a plain loop).
  explicit WorkerPool(int threads = 1);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;
  int threads() const { return int(helpers_.size()) + 1; }

  /// Calls f(i) for every i in [0, n), on the caller's thread and the helpers'.
  template <class F>
  void run(size_t n, F& f) {
    if (helpers_.empty() || n < 2) {
      for (size_t i = 0; i < n; ++i) f(i);
      return;
    }
    job_ = [](void* ctx, size_t i) { (*static_cast<F*>(ctx))(i); };
    ctx_ = &f;
    dispatch(n);
  }

  /// Items run on a helper so far (a test's evidence that helpers took part).
  uint64_t helped() const { return helped_.load(std::memory_order_relaxed); }

 private:
  void dispatch(size_t n);
  void work();     ///< takes items until none is left
  void helper();   ///< a helper thread's loop
  void (*job_)(void*, size_t) = nullptr;
  void* ctx_ = nullptr;
  size_t n_ = 0;
  std::atomic<size_t> next_{0};
  std::atomic<uint32_t> go_{0}, back_{0};
  std::atomic<bool> quit_{false};
  std::atomic<uint64_t> helped_{0};
  std::vector<std::thread> helpers_;
};

}  // namespace mar
