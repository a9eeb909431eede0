#pragma once
// Heap-allocation counter for "the hot path allocates nothing" tests.
//
// Include this header in exactly ONE translation unit of a test binary: it replaces the global operator
// new/delete and, outside AddressSanitizer builds, interposes glibc's malloc family (Eigen and Bullet call
// malloc directly). Under AddressSanitizer the sanitizer owns malloc, so only operator new is counted and
// ROME_COUNT_MALLOC is 0.
//
//   g_allocations = 0; g_counting = true;  hot_path();  g_counting = false;  EXPECT_EQ(g_allocations, 0);
// or  EXPECT_EQ(rome::test::CountAllocations([&] { hot_path(); }), 0);

#include <atomic>
#include <cstdlib>
#include <new>

namespace rome::test {
inline std::atomic<bool> g_counting{false};
inline std::atomic<long> g_allocations{0};

inline void CountOne() {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
}

/// Number of heap allocations made while `f` runs.
template <class F>
long CountAllocations(F&& f) {
  g_allocations = 0;
  g_counting = true;
  f();
  g_counting = false;
  return g_allocations;
}
}  // namespace rome::test

using rome::test::g_allocations;
using rome::test::g_counting;

#if defined(__SANITIZE_ADDRESS__)
#define ROME_COUNT_MALLOC 0
#else
#define ROME_COUNT_MALLOC 1
#endif
/// Whether malloc-family calls are counted (false under AddressSanitizer: only operator new is).
[[maybe_unused]] constexpr bool kCountsMalloc = ROME_COUNT_MALLOC;

#if ROME_COUNT_MALLOC
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void __libc_free(void*);
void* malloc(std::size_t n) {
  rome::test::CountOne();
  return __libc_malloc(n);
}
void* calloc(std::size_t a, std::size_t b) {
  rome::test::CountOne();
  return __libc_calloc(a, b);
}
void* realloc(void* p, std::size_t n) {
  rome::test::CountOne();
  return __libc_realloc(p, n);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t n) {
  rome::test::CountOne();
  *out = __libc_memalign(alignment, n);
  return *out ? 0 : 12;  // ENOMEM
}
void* aligned_alloc(std::size_t alignment, std::size_t n) {
  rome::test::CountOne();
  return __libc_memalign(alignment, n);
}
void free(void* p) { __libc_free(p); }
}
#endif

namespace rome::test {
/// operator new goes through malloc; it counts itself only when malloc is not counted already.
[[gnu::noinline]] inline void* CountedNew(std::size_t size) {
  if (!ROME_COUNT_MALLOC) CountOne();
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
}  // namespace rome::test

void* operator new(std::size_t size) { return rome::test::CountedNew(size); }
void* operator new[](std::size_t size) { return rome::test::CountedNew(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
