#include "app/alloc_count.h"

#include <cstdlib>
#include <new>

namespace {
// Per thread: the frame's own allocations, not those of device and bench threads (which
// open devices and may allocate by design).
thread_local uint64_t t_allocs = 0;
}

uint64_t mar::heap_allocation_count() { return t_allocs; }

#if defined(__has_feature)
#if __has_feature(thread_sanitizer) || __has_feature(address_sanitizer)
#define MARIONETTE_ALLOC_HOOK 1
#endif
#endif
#if defined(__SANITIZE_THREAD__) || defined(__SANITIZE_ADDRESS__)
#define MARIONETTE_ALLOC_HOOK 1
#endif

#ifdef MARIONETTE_ALLOC_HOOK
// Under ThreadSanitizer (whose runtime defines operator new itself) and AddressSanitizer the
// sanitizer's allocator calls this hook for every allocation — malloc and calloc too, which a
// replaced operator new never sees (Eigen, C libraries, SDL) — so the sanitizer builds prove
// the stricter thing: the frame thread calls no allocator at all.
extern "C" int __sanitizer_install_malloc_and_free_hooks(void (*on_malloc)(const volatile void*, std::size_t),
                                                         void (*on_free)(const volatile void*));
namespace {
void on_alloc(const volatile void*, std::size_t) { ++t_allocs; }
void on_free(const volatile void*) {}
[[maybe_unused]] const int g_hooked = __sanitizer_install_malloc_and_free_hooks(on_alloc, on_free);
}  // namespace
#else
void* operator new(std::size_t n) {
  ++t_allocs;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  ++t_allocs;
  return std::malloc(n ? n : 1);
}
void* operator new[](std::size_t n, const std::nothrow_t& t) noexcept { return operator new(n, t); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
#endif
