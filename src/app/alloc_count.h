// Counting allocations per thread: linked into the marionette program (its stats report
// allocations after warm-up) and into the "allocates nothing" tests. A plain build counts a
// replaced global operator new; the ASan and TSan builds count every call of the sanitizer's
// allocator (malloc too). Only executables that link alloc_count.cpp get it.
#pragma once

#include <cstdint>

namespace mar {

/// Allocations (operator new; under a sanitizer, malloc as well) made by the calling thread so
/// far (a thread-local counter: the frame thread's count is the frame's, whatever device
/// threads do).
uint64_t heap_allocation_count();

}  // namespace mar
