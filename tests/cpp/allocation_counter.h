// Counts every heap allocation of the test program that includes it: replaces the global
// operator new / delete. Include it from exactly one translation unit of an executable (each
// tests/cpp/test_*.cpp is one); read allocation_count() before and after the code under test.
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

namespace f16mmae::testing {
inline std::atomic<long long> g_allocations{0};
inline long long allocation_count() { return g_allocations.load(); }
}  // namespace f16mmae::testing

void* operator new(std::size_t n) {
  ++f16mmae::testing::g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
