// Counting replacement of global operator new for "allocates nothing" tests. Link
// alloc_counter.cpp into the test executable (only those tests: it replaces new/delete).
#pragma once

namespace mar::test {

/// Number of operator new calls in this process so far.
long allocation_count();

}  // namespace mar::test
