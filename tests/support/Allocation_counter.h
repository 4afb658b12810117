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
// The nothrow form too: otherwise it stays the runtime's (ASan's own allocator under
// EXTREMAL_SANITIZE) while the delete below frees with free(), a mismatch ASan reports (seen in
// libfreeimage's exit handler, loaded through OpenCASCADE).
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  ++extremal::test::g_allocations;
  return std::malloc(n ? n : 1);
}
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
// Not inlined: inlined into a caller, GCC sees free() on a pointer from operator new and warns
// (-Wmismatched-new-delete) although the two replacements here are a matched pair.
[[gnu::noinline]] void operator delete(void* p) noexcept { std::free(p); }
[[gnu::noinline]] void operator delete(void* p, std::size_t) noexcept { std::free(p); }
