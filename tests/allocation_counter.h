#pragma once
// Counts the heap allocations made inside a window a test opens and closes, on any thread: the
// global operator new (every form) and the C allocator (malloc, calloc, realloc, aligned_alloc,
// posix_memalign, memalign — Eigen's dynamic matrices allocate there, not through operator new)
// are replaced in the test executable that links allocation_counter.cpp, so that they also count
// the allocations of the shared libraries it loads.
//
// Under AddressSanitizer the sanitizer owns the allocator: nothing is replaced and kCounts is
// false (the tests skip themselves).
#include <cstdint>

namespace sweep::test {

#if defined(SWEEP_SANITIZED)
#define SWEEP_TEST_COUNTS_ALLOCATIONS 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SWEEP_TEST_COUNTS_ALLOCATIONS 0
#endif
#endif
#ifndef SWEEP_TEST_COUNTS_ALLOCATIONS
#define SWEEP_TEST_COUNTS_ALLOCATIONS 1
#endif
inline constexpr bool kCounts = SWEEP_TEST_COUNTS_ALLOCATIONS;

struct AllocationCounts {
  std::int64_t news = 0;     // calls of operator new / new[]
  std::int64_t mallocs = 0;  // calls of the C allocator made directly (not by operator new)
  std::int64_t total() const { return news + mallocs; }
};

// Opens the window: counts are reset and counted from now on until close_allocation_window().
void open_allocation_window();
AllocationCounts close_allocation_window();

}  // namespace sweep::test
