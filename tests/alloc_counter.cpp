#include "alloc_counter.h"

#include "app/alloc_count.h"

long mar::test::allocation_count() { return long(mar::heap_allocation_count()); }
