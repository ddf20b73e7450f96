// The no-allocation tests' two checks: a counting global operator new, which
// sees every heap allocation, and Eigen's runtime malloc guard (checked build:
// eigen_assert on, EIGEN_RUNTIME_NO_MALLOC), which aborts on an Eigen one.
// Both are defined in alloc_guard.cpp, which a test executable links once
// (the object library gimbalsim_test_alloc_guard, tests/CMakeLists.txt).
#pragma once

#include <atomic>

namespace gimbalsim::test {

/// Allocations made through the global operator new (and new[]) so far.
extern std::atomic<long long> g_allocations;

/// Allocations counted for one new and delete of a std::vector (the
/// counter's self-check: at least 1 when this executable's operator new counts).
long long probeAllocations();

/// Switches Eigen's runtime malloc guard; a no-op outside the checked build.
void setEigenMallocAllowed(bool allowed);

/// Prints a note to stderr when Eigen's guard is off (not the checked build),
/// so that only the counting allocator checks.
void noteIfNotCheckedBuild();

}  // namespace gimbalsim::test
