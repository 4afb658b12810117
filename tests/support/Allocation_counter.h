// Counts heap allocations so a test can assert that a hot path makes none. Replaces the global
// operator new and delete: include it from exactly one translation unit of a test program.
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

namespace extremal::test {
inline std::atomic<long> g_allocations{0};
}  // namespace extremal::test

void* operator new(std::size_t n) {
  ++extremal::test::g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
