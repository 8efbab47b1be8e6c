// Counting replacement of global operator new: linked into the marionette program (its
// stats report allocations after warm-up) and into the "allocates nothing" tests. Only
// executables that link alloc_count.cpp get it.
#pragma once

#include <cstdint>

namespace mar {

/// operator new calls made by the calling thread so far (a thread-local counter: the frame
/// thread's count is the frame's, whatever device threads do).
uint64_t heap_allocation_count();

}  // namespace mar
