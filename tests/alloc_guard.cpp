// Definitions of alloc_guard.hpp: the counting global operator new (exactly
// one per test executable, as this file is linked once) and the switch of
// Eigen's malloc guard.
#include "alloc_guard.hpp"

#include <cstdio>
#include <cstdlib>
#include <new>
#include <vector>

#ifdef EIGEN_RUNTIME_NO_MALLOC
#include <Eigen/Core>
#endif

namespace gimbalsim::test {

std::atomic<long long> g_allocations{0};

long long probeAllocations() {
  const long long before = g_allocations.load();
  std::vector<double>* volatile p = new std::vector<double>(100);
  delete p;
  return g_allocations.load() - before;
}

void setEigenMallocAllowed(bool allowed) {
#ifdef EIGEN_RUNTIME_NO_MALLOC
  Eigen::internal::set_is_malloc_allowed(allowed);
#else
  (void)allowed;
#endif
}

void noteIfNotCheckedBuild() {
#if !defined(EIGEN_RUNTIME_NO_MALLOC) || defined(NDEBUG)
  std::fprintf(stderr, "note: not the checked build; only the counting allocator is active\n");
#endif
}

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
