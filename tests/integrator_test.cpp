// The fixed-step RK4: order, switch location, caps and failure reporting.
#include <gtest/gtest.h>

#include <limits>

#include "gimbalsim/dynamics/simulate.hpp"
#include "test_util.hpp"

namespace gimbalsim {
namespace {

TEST(Integrator, Rk4IsFourthOrderOnTheIdealScene) {
  auto finalQ = [](double h) {
    const Model m = test::scene("paper_ideal", {"sim.step=" + std::to_string(h), "sim.output_interval=0.016"});
    return test::runTo<FloatingIdeal>(m, 1.6);
  };
  const auto ref = finalQ(1.0e-4);
  std::vector<double> err;
  for (double h : {8e-3, 4e-3, 2e-3}) {
    const auto s = finalQ(h);
    err.push_back(std::max((s.q - ref.q).norm(), (s.v - ref.v).norm()));
  }
  for (size_t i = 0; i + 1 < err.size(); ++i) {
    const double ratio = err[i] / err[i + 1];
    EXPECT_GT(ratio, 13.0) << "errors " << err[i] << " -> " << err[i + 1];
    EXPECT_LT(ratio, 19.0) << "errors " << err[i] << " -> " << err[i + 1];
  }
}

TEST(Integrator, StepAdvancesExactlyOneStep) {
  const Model m = test::scene("paper_clearance");
  Data<FloatingClearanceFriction> d(m);
  auto s = initialState<FloatingClearanceFriction>(m);
  for (int k = 1; k <= 100; ++k) {
    ASSERT_EQ(step(m, d, s, test::sceneInput(m)), StepStatus::Ok);
    EXPECT_NEAR(s.t, k * m.integrator.step, 1e-12);
  }
  EXPECT_EQ(d.stats.steps, 100);
  EXPECT_GE(d.stats.substeps, 100);
  EXPECT_LE(d.stats.max_substeps_in_step, substepCap(m));
}

/// Runs until the first located impact; returns the state at its end of step.
template <class V>
double firstImpactVelocity(const Model& m, double* t_onset) {
  Data<V> d(m);
  auto s = initialState<V>(m);
  for (int k = 0; k < 100000 && d.stats.impacts == 0; ++k) {
    EXPECT_EQ(step(m, d, s, test::sceneInput(m)), StepStatus::Ok);
  }
  EXPECT_EQ(d.stats.impacts, 1);
  *t_onset = d.stats.last_onset_time;
  return s.v0;
}

TEST(Integrator, ImpactOnsetIsLocatedAndV0CapturedThere) {
  // The same impact with a coarse and a very fine sub-step: the located onset
  // time and impact velocity agree, and v0 is a positive approach speed.
  double t_coarse, t_fine, t_big;
  const Model coarse = test::scene("paper_clearance", {"friction.law=none"});
  const Model fine = test::scene("paper_clearance", {"friction.law=none", "sim.substep=1e-7", "sim.event_tol=1e-11"});
  const Model big = test::scene("paper_clearance", {"friction.law=none", "sim.substep=1e-3"});
  const double v_coarse = firstImpactVelocity<FloatingClearance>(coarse, &t_coarse);
  const double v_fine = firstImpactVelocity<FloatingClearance>(fine, &t_fine);
  const double v_big = firstImpactVelocity<FloatingClearance>(big, &t_big);
  EXPECT_GT(v_fine, 1e-4);
  EXPECT_NEAR(t_coarse, t_fine, 2e-9);
  EXPECT_NEAR(v_coarse, v_fine, 1e-7 * v_fine);
  // Even without sub-steps (one RK4 step per ms) the step-back locates it.
  EXPECT_NEAR(t_big, t_fine, 2e-9);
  EXPECT_NEAR(v_big, v_fine, 1e-4 * v_fine);
}

TEST(Integrator, SubstepCapStopsTheStepAndSaysSo) {
  const Model m = test::scene("paper_clearance", {"sim.max_substeps=3"});
  Data<FloatingClearanceFriction> d(m);
  auto s = initialState<FloatingClearanceFriction>(m);
  StepStatus st = StepStatus::Ok;
  for (int k = 0; k < 1000 && st == StepStatus::Ok; ++k) st = step(m, d, s, test::sceneInput(m));
  EXPECT_EQ(st, StepStatus::SubstepCap);
  EXPECT_GT(d.fail_time, 0.0);
  EXPECT_LE(d.stats.max_substeps_in_step, 3);
}

TEST(Integrator, NonFiniteInputIsDetectedNotIntegrated) {
  const Model m = test::scene("paper_ideal");
  Data<FloatingIdeal> d(m);
  auto s = initialState<FloatingIdeal>(m);
  const auto before = s;
  Input u;
  u.tau << 5.0, std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(step(m, d, s, u), StepStatus::NonFinite);
  EXPECT_EQ(s.q, before.q) << "a failed step must not advance the state";
  EXPECT_EQ(s.t, before.t);
}

TEST(Integrator, DivergenceStopsTheRunWithADiagnosticAndKeepsGoodRows) {
  // Contact 1e6 times too soft: the journal sinks through the bearing.
  const Model m = test::scene("paper_clearance", {"contact.stiffness_scale=1e-6", "sim.duration=1"});
  std::vector<Row> rows;
  const RunResult r = simulate(m, [&](const Row& row) { rows.push_back(row); });
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("penetration"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("t = "), std::string::npos) << r.error;
  ASSERT_FALSE(rows.empty());
  EXPECT_LT(rows.back().t, 1.0);
  for (const Row& row : rows) {
    for (int i = 0; i < kNumColumns; ++i) ASSERT_TRUE(std::isfinite(rowData(row)[i]));
  }
  // A torque that spins the joints past the velocity limit.
  const Model v = test::scene("paper_ideal", {"torque.tau1=1e6", "sim.velocity_limit=100"});
  const RunResult rv = simulate(v, [](const Row&) {});
  EXPECT_FALSE(rv.ok);
  EXPECT_NE(rv.error.find("velocity"), std::string::npos) << rv.error;
}

TEST(Integrator, ClearanceRunReproducesThePapersQualitativeResults) {
  // Paper section 4: impacts severe at first, then weaker; finally continuous
  // contact; joint force peaks about 20x the ideal joint's (we require > 5x).
  const Model m = test::scene("paper_clearance");
  double early_peak = 0.0, late_peak = 0.0;
  const RunResult r = simulate(m, [&](const Row& row) {
    (row.t < 0.5 ? early_peak : late_peak) = std::max(row.t < 0.5 ? early_peak : late_peak, row.fn);
  });
  ASSERT_TRUE(r.ok) << r.error;
  const Model mi = test::scene("paper_ideal");
  const RunResult ri = simulate(mi, [](const Row&) {});
  ASSERT_TRUE(ri.ok);
  EXPECT_GT(r.stats.impacts, 3);
  EXPECT_TRUE(r.in_contact_at_end);
  EXPECT_LT(r.stats.last_onset_time, 4.0) << "continuous contact should set in";
  EXPECT_GT(r.stats.peak_fn, late_peak);
  EXPECT_GT(r.peak_joint2_force, 5.0 * ri.peak_joint2_force);
}

}  // namespace
}  // namespace gimbalsim
