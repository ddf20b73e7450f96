// A counting global operator new for the no-allocation tests of the HIL side
// (include in exactly one .cpp per test executable). Eigen's own guard is
// switched with setEigenMallocAllowed() in the checked build.
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

namespace gimbalsim::test {
inline std::atomic<long long> g_allocations{0};
}  // namespace gimbalsim::test

// GCC flags free() of memory from these very operators as "mismatched" once
// they are inlined; they are matched (malloc/free throughout).
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

void* operator new(std::size_t n) {
  ++gimbalsim::test::g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
