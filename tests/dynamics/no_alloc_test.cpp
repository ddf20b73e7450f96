// After construction a step makes zero heap allocations: a counting global
// operator new catches any allocation, and in the checked build (eigen_assert
// on, EIGEN_RUNTIME_NO_MALLOC) Eigen's own guard aborts on one.
#include <gtest/gtest.h>

#include "alloc_guard.hpp"
#include "test_util.hpp"

namespace gimbalsim {
namespace {

using test::g_allocations;
using test::setEigenMallocAllowed;

TEST(NoAlloc, TheCounterSeesAllocations) {
  EXPECT_GE(test::probeAllocations(), 1);
}

template <class V>
void checkNoAllocation(const Scene& sc, int steps) {
  const Model& m = sc.model;
  Data<V> d(m);
  State<V> s = initialState<V>(sc.run.initial);
  const Input u{sc.run.torque};
  for (int k = 0; k < 10; ++k) ASSERT_EQ(step(m, d, s, u).status, StepStatus::Ok);  // warm-up
  const long long before = g_allocations.load();
  setEigenMallocAllowed(false);
  StepStatus st = StepStatus::Ok;
  for (int k = 0; k < steps && st == StepStatus::Ok; ++k) st = step(m, d, s, u).status;
  setEigenMallocAllowed(true);
  ASSERT_EQ(st, StepStatus::Ok);
  EXPECT_EQ(g_allocations.load() - before, 0) << "heap allocations during " << steps << " steps";
  if constexpr (V::kContact) EXPECT_GT(d.stats.impacts, 0) << "the window must cover impacts";
}

TEST(NoAlloc, StepOfEveryVariantAllocatesNothing) {
  test::noteIfNotCheckedBuild();
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

TEST(NoAlloc, StepOfTheClearanceInEitherJointShapesAllocatesNothing) {
  // The shipped scenes of those shapes, each through its impacts at either end.
  using CK = ClearanceKind;
  checkNoAllocation<Variant<true, CK::Ideal, CK::Spatial, true>>(test::scene("paper_spatial2"), 500);
  checkNoAllocation<Variant<true, CK::Planar, CK::Planar, true>>(test::scene("paper_both_planar"), 500);
  checkNoAllocation<Variant<true, CK::Spatial, CK::Spatial, true>>(test::scene("paper_both_spatial"), 800);
  checkNoAllocation<Variant<false, CK::Spatial, CK::Planar, false>>(
      test::scene("paper_both_planar", {"structure.base=fixed", "structure.joint1=spatial", "friction.law=none",
                                        "sim.substep_policy=adaptive"}),
      500);
}

TEST(NoAlloc, FailingStepAllocatesNothingEither) {
  const Scene sc = test::scene("paper_clearance", {"sim.max_substeps=3"});
  const Model& m = sc.model;
  Data<FloatingClearanceFriction> d(m);
  auto s = initialState<FloatingClearanceFriction>(sc.run.initial);
  const long long before = g_allocations.load();
  setEigenMallocAllowed(false);
  StepStatus st = StepStatus::Ok;
  for (int k = 0; k < 1000 && st == StepStatus::Ok; ++k) st = step(m, d, s, Input{sc.run.torque}).status;
  setEigenMallocAllowed(true);
  EXPECT_EQ(st, StepStatus::SubstepCap);
  EXPECT_EQ(g_allocations.load() - before, 0);
}

}  // namespace
}  // namespace gimbalsim
