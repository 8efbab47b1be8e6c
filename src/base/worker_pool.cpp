#include "base/worker_pool.h"

#include <algorithm>

namespace mar {

WorkerPool::WorkerPool(int threads) {
  const int helpers = std::clamp(threads, 1, 64) - 1;
  helpers_.reserve(size_t(helpers));
  for (int k = 0; k < helpers; ++k) helpers_.emplace_back([this] { helper(); });
}

WorkerPool::~WorkerPool() {
  quit_.store(true, std::memory_order_release);
  go_.fetch_add(1, std::memory_order_release);
  go_.notify_all();
  for (std::thread& t : helpers_) t.join();
}

void WorkerPool::work() {
  for (size_t i; (i = next_.fetch_add(1, std::memory_order_acq_rel)) < n_;) job_(ctx_, i);
}

void WorkerPool::dispatch(size_t n) {
  // The job is written before go_ is released: a helper reads it after acquiring go_. Every
  // helper comes back (back_) before run() returns, so none still reads this job when the
  // next one is written.
  n_ = n;
  next_.store(0, std::memory_order_relaxed);
  const uint32_t before = back_.load(std::memory_order_acquire);
  go_.fetch_add(1, std::memory_order_release);
  go_.notify_all();
  work();
  const uint32_t want = before + uint32_t(helpers_.size());
  for (uint32_t b; (b = back_.load(std::memory_order_acquire)) != want;) back_.wait(b, std::memory_order_acquire);
}

void WorkerPool::helper() {
  uint32_t seen = 0;
  for (;;) {
    go_.wait(seen, std::memory_order_acquire);
    seen = go_.load(std::memory_order_acquire);
    if (quit_.load(std::memory_order_acquire)) return;
    uint64_t mine = 0;
    for (size_t i; (i = next_.fetch_add(1, std::memory_order_acq_rel)) < n_; ++mine) job_(ctx_, i);
    if (mine) helped_.fetch_add(mine, std::memory_order_relaxed);
    back_.fetch_add(1, std::memory_order_release);
    back_.notify_one();
  }
}

}  // namespace mar
