// The call-by-call Simulator (simulator.hpp, behind the Python package):
// stepping it gives the rows simulate() gives, its checkpoints restore
// bit for bit, a wrong checkpoint is refused, and step(), run() and output()
// allocate nothing once built.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <stdexcept>
#include <vector>

#include "alloc_guard.hpp"
#include "gimbalsim/dynamics/simulate.hpp"
#include "gimbalsim/dynamics/saved_state.hpp"
#include "gimbalsim/dynamics/simulator.hpp"
#include "test_util.hpp"

namespace gimbalsim {
namespace {

using test::g_allocations;

std::vector<double> simulateRows(const Scene& sc) {
  std::vector<double> rows;
  const RunResult r =
      simulate(sc, [&](const Row& row) { rows.insert(rows.end(), rowData(row), rowData(row) + kNumColumns); });
  EXPECT_TRUE(r.ok) << r.error;
  return rows;
}

bool sameBits(const double* a, const double* b, std::size_t n) { return std::memcmp(a, b, n * sizeof(double)) == 0; }

TEST(Simulator, StepsGiveTheRowsOfSimulate) {
  for (const char* policy : {"fixed", "adaptive"}) {
    SCOPED_TRACE(policy);
    const Scene sc = test::scene("paper_clearance", {"sim.duration=0.4", "friction.law=coulomb_stick",
                                                     std::string("sim.substep_policy=") + policy});
    const std::vector<double> expected = simulateRows(sc);
    Simulator sim(sc);
    const long long n = static_cast<long long>(expected.size() / kNumColumns) - 1;
    std::vector<double> tau(2 * n), rows(n * kNumColumns);
    for (long long i = 0; i < n; ++i) {
      tau[2 * i] = sc.run.torque(0);
      tau[2 * i + 1] = sc.run.torque(1);
    }
    const Row first = sim.output();
    EXPECT_TRUE(sameBits(rowData(first), expected.data(), kNumColumns));
    long long done = 0;
    ASSERT_TRUE(sim.run(tau.data(), n, rows.data(), done).ok());
    EXPECT_EQ(done, n);
    EXPECT_TRUE(sameBits(rows.data(), expected.data() + kNumColumns, rows.size()));
    EXPECT_DOUBLE_EQ(sim.time(), static_cast<double>(n) * sc.model.integrator.step);
  }
}

TEST(Simulator, RestoredCheckpointResumesBitForBit) {
  const Scene sc = test::scene("paper_clearance", {"friction.law=coulomb_stick"});
  Simulator a(sc), b(sc);
  ASSERT_TRUE(a.step(sc.run.torque, 150).ok());
  const SavedState saved = a.save();
  ASSERT_TRUE(a.step(sc.run.torque, 200).ok());
  b.restore(saved);  // b has a fresh workspace and had never stepped
  ASSERT_TRUE(b.step(sc.run.torque, 200).ok());
  const Row ra = a.output(), rb = b.output();
  EXPECT_TRUE(sameBits(rowData(ra), rowData(rb), kNumColumns));
  EXPECT_GT(ra.ecc2, 0.0);
}

TEST(Simulator, ACheckpointUnderItsVariantsOldNameRestores) {
  // Saved before both joints were named alike: floating_clearance_friction is floating_ideal_planar_friction.
  const Scene sc = test::scene("paper_clearance");
  Simulator a(sc), b(sc);
  ASSERT_TRUE(a.step(sc.run.torque, 100).ok());
  SavedState saved = a.save();
  EXPECT_EQ(saved.variant, "floating_ideal_planar_friction");
  saved.variant = "floating_clearance_friction";
  b.restore(saved);
  ASSERT_TRUE(a.step(sc.run.torque, 50).ok());
  ASSERT_TRUE(b.step(sc.run.torque, 50).ok());
  const Row ra = a.output(), rb = b.output();
  EXPECT_TRUE(sameBits(rowData(ra), rowData(rb), kNumColumns));
  saved.variant = "floating_spatial1_ideal_friction";  // an old name of another variant
  EXPECT_THROW(b.restore(saved), std::invalid_argument);
}

TEST(Simulator, RefusesACheckpointOfAnotherVariant) {
  Simulator clearance(test::scene("paper_clearance"));
  Simulator ideal(test::scene("paper_ideal"));
  EXPECT_THROW(clearance.restore(ideal.save()), std::invalid_argument);
  SavedState bad = clearance.save();
  bad.q.pop_back();
  EXPECT_THROW(clearance.restore(bad), std::invalid_argument);
  bad = clearance.save();
  bad.friction_mode = 7;
  EXPECT_THROW(clearance.restore(bad), std::invalid_argument);
}

// A checkpoint from outside is checked as a scene is (saved_state.hpp): the
// issue's t = 1e300 (one step later t was -9.2e15) and v0 = NaN are refused
// naming the field, and leave the simulator as it was.
TEST(Simulator, RefusesAStateFromOutsideNamingTheField) {
  const Scene sc = test::scene("paper_clearance");
  Simulator sim(sc);
  const SavedState good = sim.save();
  auto refusal = [&](SavedState bad) {
    try {
      sim.restore(bad);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  SavedState bad = good;
  bad.t = 1e300;
  EXPECT_EQ(refusal(bad).rfind("State.t = 1", 0), 0u) << refusal(bad);
  EXPECT_NE(refusal(bad).find("e+300 s: beyond what the step counter reaches"), std::string::npos) << refusal(bad);
  bad = good;
  ASSERT_EQ(bad.v0.size(), 1u);  // one planar contact end
  bad.v0[0] = std::nan("");
  EXPECT_EQ(refusal(bad), "State.v0[0] = nan: must be finite");
  bad = good;
  bad.v0.push_back(0.0);
  bad.in_contact.push_back(false);
  EXPECT_EQ(refusal(bad).rfind("State.in_contact and State.v0 hold 2 and 2 values", 0), 0u) << refusal(bad);
  bad = good;
  bad.q[3] = 2.0;  // the base quaternion's w
  EXPECT_NE(refusal(bad).find("State.q[3:7]"), std::string::npos) << refusal(bad);
  EXPECT_EQ(sim.save().t, good.t);
  // the largest time the check lets through steps on, forward
  bad = good;
  bad.t = static_cast<double>(kMaxRestoredStepIndex) * sc.model.integrator.step;
  sim.restore(bad);
  ASSERT_TRUE(sim.step(Vec2::Zero(), 2).ok());
  EXPECT_GT(sim.time(), bad.t);
}

TEST(Simulator, StepRunAndOutputAllocateNothing) {
  test::noteIfNotCheckedBuild();
  ASSERT_GT(test::probeAllocations(), 0) << "the counting allocator is not linked";
  for (const char* policy : {"fixed", "adaptive"}) {
    SCOPED_TRACE(policy);
    // (adaptive error control needs a friction law without plain Coulomb's jump)
    const Scene sc = test::scene("paper_clearance", {std::string("sim.substep_policy=") + policy,
                                                     "friction.law=coulomb_stick"});
    Simulator sim(sc);
    constexpr long long kN = 200;
    std::vector<double> tau(2 * kN, 10.0), rows(kN * kNumColumns);
    long long done = 0;
    const long long before = g_allocations.load();
    test::setEigenMallocAllowed(false);
    const StepResult a = sim.step(sc.run.torque, 300);
    const StepResult b = sim.run(tau.data(), kN, rows.data(), done);
    const Row r = sim.output();
    test::setEigenMallocAllowed(true);
    EXPECT_EQ(g_allocations.load() - before, 0);
    EXPECT_TRUE(a.ok() && b.ok());
    EXPECT_GT(r.t, 0.0);
  }
}

}  // namespace
}  // namespace gimbalsim
