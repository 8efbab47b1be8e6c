// Allocation count for "allocates nothing" tests: link alloc_counter.cpp and
// src/app/alloc_count.cpp (the program's counting operator new) into the test executable.
#pragma once

namespace mar::test {

/// Number of operator new calls in this process so far.
long allocation_count();

}  // namespace mar::test
