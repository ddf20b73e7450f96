// After construction a step makes zero heap allocations: a counting global
// operator new catches any allocation, and in the checked build (eigen_assert
// on, EIGEN_RUNTIME_NO_MALLOC) Eigen's own guard aborts on one.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "test_util.hpp"

namespace {
std::atomic<long long> g_allocations{0};
}

void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace gimbalsim {
namespace {

void setEigenMallocAllowed(bool allowed) {
#ifdef EIGEN_RUNTIME_NO_MALLOC
  Eigen::internal::set_is_malloc_allowed(allowed);
#else
  (void)allowed;
#endif
}

TEST(NoAlloc, TheCounterSeesAllocations) {
  const long long before = g_allocations.load();
  std::vector<double>* volatile p = new std::vector<double>(100);
  delete p;
  EXPECT_GE(g_allocations.load() - before, 1);
}

template <class V>
void checkNoAllocation(const Model& m, int steps) {
  Data<V> d(m);
  State<V> s = initialState<V>(m);
  const Input u = test::sceneInput(m);
  for (int k = 0; k < 10; ++k) ASSERT_EQ(step(m, d, s, u), StepStatus::Ok);  // warm-up
  const long long before = g_allocations.load();
  setEigenMallocAllowed(false);
  StepStatus st = StepStatus::Ok;
  for (int k = 0; k < steps && st == StepStatus::Ok; ++k) st = step(m, d, s, u);
  setEigenMallocAllowed(true);
  ASSERT_EQ(st, StepStatus::Ok);
  EXPECT_EQ(g_allocations.load() - before, 0) << "heap allocations during " << steps << " steps";
  if constexpr (V::kClearance) EXPECT_GT(d.stats.impacts, 0) << "the window must cover impacts";
}

TEST(NoAlloc, StepOfEveryVariantAllocatesNothing) {
#if !defined(EIGEN_RUNTIME_NO_MALLOC) || defined(NDEBUG)
  std::fprintf(stderr, "note: not the checked build; only the counting allocator is active\n");
#endif
  checkNoAllocation<FloatingIdeal>(test::scene("paper_ideal"), 500);
  checkNoAllocation<FloatingClearance>(test::scene("paper_clearance", {"friction.law=none"}), 300);
  checkNoAllocation<FloatingClearanceFriction>(test::scene("paper_clearance"), 300);
  checkNoAllocation<FixedIdeal>(test::scene("paper_ideal", {"structure.base=fixed"}), 500);
  checkNoAllocation<FixedClearance>(test::scene("paper_clearance", {"structure.base=fixed", "friction.law=none"}), 300);
  checkNoAllocation<FixedClearanceFriction>(test::scene("paper_clearance", {"structure.base=fixed"}), 300);
}

TEST(NoAlloc, AdaptivePolicyAndCoulombStickAllocateNothing) {
  const std::string adaptive = "sim.substep_policy=adaptive";
  checkNoAllocation<FloatingClearanceFriction>(test::scene("paper_clearance", {adaptive, "friction.law=coulomb_stick"}), 500);
  checkNoAllocation<FloatingClearanceFriction>(test::scene("paper_clearance", {"friction.law=coulomb_stick"}), 300);
  checkNoAllocation<FloatingClearanceFriction>(test::scene("paper_clearance", {adaptive, "friction.law=ambrosio"}), 300);
  checkNoAllocation<FloatingClearance>(test::scene("paper_clearance", {adaptive, "friction.law=none"}), 300);
  checkNoAllocation<FixedClearanceFriction>(
      test::scene("paper_clearance", {adaptive, "structure.base=fixed", "friction.law=coulomb_stick"}), 300);
  checkNoAllocation<FloatingIdeal>(test::scene("paper_ideal", {adaptive}), 300);
}

TEST(NoAlloc, FailingStepAllocatesNothingEither) {
  const Model m = test::scene("paper_clearance", {"sim.max_substeps=3"});
  Data<FloatingClearanceFriction> d(m);
  auto s = initialState<FloatingClearanceFriction>(m);
  const long long before = g_allocations.load();
  setEigenMallocAllowed(false);
  StepStatus st = StepStatus::Ok;
  for (int k = 0; k < 1000 && st == StepStatus::Ok; ++k) st = step(m, d, s, test::sceneInput(m));
  setEigenMallocAllowed(true);
  EXPECT_EQ(st, StepStatus::SubstepCap);
  EXPECT_EQ(g_allocations.load() - before, 0);
}

}  // namespace
}  // namespace gimbalsim
