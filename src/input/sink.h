// A frame's fixed-capacity output: filled without allocating; what does not fit is counted.
#pragma once

#include <cstddef>
#include <cstdint>

namespace mar {

template <class T>
struct FixedSink {
  T* data = nullptr;
  size_t cap = 0, n = 0;
  uint64_t dropped = 0;
  void push(const T& v) {
    if (n < cap) data[n++] = v;
    else ++dropped;
  }
};

}  // namespace mar
