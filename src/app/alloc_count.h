// Counting replacement of global operator new: linked into the marionette program (its
// stats report allocations after warm-up) and into the "allocates nothing" tests. Only
// executables that link alloc_count.cpp get it.
#pragma once

#include <cstdint>

namespace mar {

/// operator new calls in this process so far (one relaxed atomic: lock-free).
uint64_t heap_allocation_count();

}  // namespace mar
