// The fixed-step RK4: order, switch location, caps and failure reporting.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "gimbalsim/dynamics/integrator.hpp"
#include "gimbalsim/dynamics/simulate.hpp"
#include "test_util.hpp"

namespace gimbalsim {
namespace {

TEST(Integrator, Rk4IsFourthOrderOnTheIdealScene) {
  auto finalQ = [](double h) {
    const Scene sc = test::scene("paper_ideal", {"sim.step=" + std::to_string(h), "sim.output_interval=0.016"});
    return test::runTo<FloatingIdeal>(sc, 1.6);
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
  const Scene sc = test::scene("paper_clearance");
  const Model& m = sc.model;
  Data<FloatingClearanceFriction> d(m);
  auto s = initialState<FloatingClearanceFriction>(sc.run.initial);
  for (int k = 1; k <= 100; ++k) {
    ASSERT_EQ(step(m, d, s, Input{sc.run.torque}).status, StepStatus::Ok);
    EXPECT_NEAR(s.t, k * m.integrator.step, 1e-12);
  }
  EXPECT_EQ(d.stats.steps, 100);
  EXPECT_GE(d.stats.substeps, 100);
  EXPECT_LE(d.stats.max_substeps_in_step, substepCap(m));
}

/// Runs until the first located impact; returns the state at its end of step.
template <class V>
double firstImpactVelocity(const Scene& sc, double* t_onset) {
  const Model& m = sc.model;
  Data<V> d(m);
  auto s = initialState<V>(sc.run.initial);
  for (int k = 0; k < 100000 && d.stats.impacts == 0; ++k) {
    EXPECT_EQ(step(m, d, s, Input{sc.run.torque}).status, StepStatus::Ok);
  }
  EXPECT_EQ(d.stats.impacts, 1);
  *t_onset = d.stats.last_onset_time;
  return s.v0[0];
}

TEST(Integrator, ImpactOnsetIsLocatedAndV0CapturedThere) {
  // The same impact with a coarse and a very fine sub-step: the located onset
  // time and impact velocity agree, and v0 is a positive approach speed.
  double t_coarse, t_fine, t_big;
  const Scene coarse = test::scene("paper_clearance", {"friction.law=none"});
  const Scene fine = test::scene("paper_clearance", {"friction.law=none", "sim.substep=1e-7", "sim.event_tol=1e-11"});
  // (min_substeps_per_impact=0: the impact check would stop the run right
  // after locating the onset, which is what this compares)
  const Scene big =
      test::scene("paper_clearance", {"friction.law=none", "sim.substep=1e-3", "sim.min_substeps_per_impact=0"});
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

TEST(Integrator, AFloorOnTheOnsetSpeedThatNeverActsChangesNothing) {
  // (pass 55) contact.v0_min = 1e-12 stopped paper_clearance at its first impact (1e-20: NaN): a stage of the
  // sub-step that crosses into the bearing, before the onset is located, scaled its damping by the previous
  // impact's v0 (0 before the first), floored at v0_min. Such a stage now takes its own approach speed, so a
  // floor below every located onset speed (above 1e-4 m/s here) gives the default floor's run, bit for bit.
  for (const char* name : {"paper_clearance", "paper_spatial2"}) {
    const RunResult base = simulate(test::scene(name, {"sim.duration=0.5"}), [](const Row&) {});
    ASSERT_TRUE(base.ok) << name << ": " << base.error;
    ASSERT_GT(base.stats.impacts, 0) << name;
    for (const char* floor : {"contact.v0_min=1e-12", "contact.v0_min=1e-300"}) {
      const RunResult r = simulate(test::scene(name, {"sim.duration=0.5", floor}), [](const Row&) {});
      ASSERT_TRUE(r.ok) << name << " " << floor << ": " << r.error;
      EXPECT_EQ(r.stats.impacts, base.stats.impacts) << name << " " << floor;
      EXPECT_EQ(r.final_q, base.final_q) << name << " " << floor;
      EXPECT_EQ(r.final_v, base.final_v) << name << " " << floor;
    }
  }
}

TEST(Integrator, SubstepCapStopsTheStepAndSaysSo) {
  const Scene sc = test::scene("paper_clearance", {"sim.max_substeps=3"});
  const Model& m = sc.model;
  Data<FloatingClearanceFriction> d(m);
  auto s = initialState<FloatingClearanceFriction>(sc.run.initial);
  StepResult st;
  for (int k = 0; k < 1000 && st.ok(); ++k) st = step(m, d, s, Input{sc.run.torque});
  EXPECT_EQ(st.status, StepStatus::SubstepCap);
  EXPECT_STREQ(st.key(), "sim.max_substeps");
  EXPECT_GT(st.time, 0.0);
  EXPECT_LE(d.stats.max_substeps_in_step, 3);
}

TEST(Integrator, NonFiniteInputIsDetectedNotIntegrated) {
  const Scene sc = test::scene("paper_ideal");
  const Model& m = sc.model;
  Data<FloatingIdeal> d(m);
  auto s = initialState<FloatingIdeal>(sc.run.initial);
  const auto before = s;
  Input u;
  u.tau << 5.0, std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(step(m, d, s, u).status, StepStatus::NonFinite);
  EXPECT_EQ(s.q, before.q) << "a failed step must not advance the state";
  EXPECT_EQ(s.t, before.t);
}

TEST(Integrator, DivergenceStopsTheRunWithADiagnosticAndKeepsGoodRows) {
  // Contact 1e6 times too soft: the journal sinks through the bearing.
  const Scene sc = test::scene("paper_clearance", {"contact.stiffness_scale=1e-6", "sim.duration=1"});
  std::vector<Row> rows;
  const RunResult r = simulate(sc, [&](const Row& row) { rows.push_back(row); });
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("penetration"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("t = "), std::string::npos) << r.error;
  ASSERT_FALSE(rows.empty());
  EXPECT_LT(rows.back().t, 1.0);
  for (const Row& row : rows) {
    for (int i = 0; i < kNumColumns; ++i) ASSERT_TRUE(std::isfinite(rowData(row)[i]));
  }
  // A torque that spins the joints past the velocity limit.
  // (invariant guards off: they would stop it first, on the momentum drift)
  const Scene v = test::scene("paper_ideal", {"torque.tau1=1e6", "sim.velocity_limit=100", "sim.momentum_tol=0",
                                              "sim.energy_tol=0"});
  const RunResult rv = simulate(v, [](const Row&) {});
  EXPECT_FALSE(rv.ok);
  EXPECT_NE(rv.error.find("velocity"), std::string::npos) << rv.error;
}

TEST(Integrator, MomentumGuardStopsADriftingRunAndKeepsGoodRows) {
  // x20 torques on the planar scene at a 1 ms step: RK4's truncation error
  // drifts the momentum by ~3e-8 of its scale. The default guard (1e-9)
  // stops the run and names the key; every row before the stop was written.
  const std::vector<std::string> sets = {"torque.tau1=100", "torque.tau2=200", "sim.duration=1"};
  std::vector<Row> rows;
  const RunResult r = simulate(test::scene("planar_ideal", sets), [&](const Row& row) { rows.push_back(row); });
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("momentum drift"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("sim.momentum_tol"), std::string::npos) << r.error;
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(static_cast<long long>(rows.size()), r.rows);
  EXPECT_LT(rows.back().t, 1.0);
  // The guard is what stopped it: off, the same run finishes with the drift.
  std::vector<std::string> off = sets;
  off.push_back("sim.momentum_tol=0");
  const RunResult r_off = simulate(test::scene("planar_ideal", off), [](const Row&) {});
  EXPECT_TRUE(r_off.ok) << r_off.error;
  EXPECT_GT(r_off.max_drift_angular / r_off.momentum_scale, 1e-9);
  // A ten times shorter step holds the momentum within the default guard.
  std::vector<std::string> fine = sets;
  fine.push_back("sim.step=1e-4");
  const RunResult r_fine = simulate(test::scene("planar_ideal", fine), [](const Row&) {});
  EXPECT_TRUE(r_fine.ok) << r_fine.error;
}

TEST(Integrator, MomentumGuardJudgesRoundOffAgainstTheChainsAngularMomentum) {
  // paper_spatial2 with the elevation torque off: the bodies turn about their own centres of mass, so
  // sum |p_i| stays at round-off (~4e-16 N s) while the base's translation rounds to ~7e-16 N s. Judged
  // against sum |p_i| alone that was a drift of 0.57 of its scale and the run stopped at its first row.
  for (const char* name : {"paper_spatial2", "paper_both_spatial"}) {
    const RunResult r = simulate(test::scene(name, {"sim.duration=0.01", "torque.tau2=0"}), [](const Row&) {});
    ASSERT_TRUE(r.ok) << name << ": " << r.error;
    EXPECT_GT(r.max_drift_linear, 0.0) << name << ": round-off drift is there, judged against a fair scale";
    EXPECT_LT(r.max_drift_linear / r.linear_scale, 1e-12) << name;
  }
}

TEST(Integrator, EnergyGuardStopsARunThatGainsEnergy) {
  // x100 stiffness, fixed base, 0.5 ms contact sub-steps with the impact check
  // off: impacts far too short for the sub-step add energy. The energy guard
  // stops the run at the first row whose balance rose above sim.energy_tol.
  // (1 ms sub-steps diverge within one step at 0.223 s since a stage entering
  // the bearing takes its own approach speed as v0, before any row sees a gain.)
  const std::vector<std::string> sets = {"structure.base=fixed", "contact.stiffness_scale=100", "sim.substep=5e-4",
                                         "sim.min_substeps_per_impact=0", "sim.duration=1"};
  const RunResult r = simulate(test::scene("paper_clearance", sets), [](const Row&) {});
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.error.find("sim.energy_tol"), std::string::npos) << r.error;
  EXPECT_LT(r.t_end, 1.0);
  std::vector<std::string> off = sets;
  off.push_back("sim.energy_tol=0");
  const RunResult r_off = simulate(test::scene("paper_clearance", off), [](const Row&) {});
  EXPECT_TRUE(r_off.ok) << r_off.error;
  EXPECT_GT(r_off.energy_rise_rel, 1e-6) << "without the guard the gain goes unnoticed";
  // With the impact check on (the default) the run stops at the first impact instead.
  std::vector<std::string> on = sets;
  on[3] = "sim.min_substeps_per_impact=4";
  const RunResult r_on = simulate(test::scene("paper_clearance", on), [](const Row&) {});
  EXPECT_FALSE(r_on.ok);
  EXPECT_NE(r_on.error.find("sim.min_substeps_per_impact"), std::string::npos) << r_on.error;
}

TEST(Integrator, HermiteGapMaxFindsATouchBetweenTheEnds) {
  // Both ends 1 um free, approaching then receding at 10 mm/s over 1 ms:
  // the cubic reaches +1.5 um in between.
  EXPECT_GT(hermiteGapMax(1e-3, -1e-6, 1e-2, -1e-6, -1e-2), 0.0);
  EXPECT_NEAR(hermiteGapMax(1e-3, -1e-6, 1e-2, -1e-6, -1e-2), -1e-6 + 0.25 * 1e-2 * 1e-3, 1e-12);
  // The same graze with the receding rate one ulp larger: the cubic term is
  // round-off (a ~ 1e-21), and the maximum (+0.1 um) must not be lost to
  // cancellation in the quadratic formula (which gave -0.18 um: no touch).
  const double r_away = -std::nextafter(1e-2, 1.0);
  EXPECT_GT(hermiteGapMax(1e-3, -2.4e-6, 1e-2, -2.4e-6, r_away), 0.0);
  EXPECT_NEAR(hermiteGapMax(1e-3, -2.4e-6, 1e-2, -2.4e-6, r_away), -2.4e-6 + 0.25 * 1e-2 * 1e-3, 1e-12);
  // Monotone approach: the larger end value.
  EXPECT_DOUBLE_EQ(hermiteGapMax(1e-3, -2e-6, 1e-3, -1e-6, 1e-3), -1e-6);
  // Receding slowly: never reaches the bearing.
  EXPECT_LT(hermiteGapMax(1e-3, -1e-6, 1e-4, -1e-6, -1e-4), 0.0);
}

TEST(Integrator, LongOuterStepSeesImpactsInsideOneRk4Interval) {
  // With a 5 ms outer step some impacts fall inside one RK4 interval whose
  // ends are both free; the sub-step is retaken shorter (straddle_retries),
  // so the run agrees with a 1 ms outer step (it was ~1e-3 rad off before).
  auto finalQ = [](const char* h, long long* retries) {
    const Scene sc = test::scene("paper_clearance",
                                 {std::string("sim.step=") + h, "sim.output_interval=0.01", "sim.substep=1e-4",
                                  "friction.law=coulomb_stick", "sim.duration=2", "sim.momentum_tol=0"});
    const RunResult r = simulate(sc, [](const Row&) {});
    EXPECT_TRUE(r.ok) << r.error;
    *retries = r.stats.straddle_retries;
    return r.final_q;
  };
  long long retries_long = 0, retries_short = 0;
  const std::vector<double> a = finalQ("5e-3", &retries_long), b = finalQ("1e-3", &retries_short);
  EXPECT_GT(retries_long, 0);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], 1e-6) << "q[" << i << "]";
}

TEST(Integrator, ClearanceRunReproducesThePapersQualitativeResults) {
  // Paper section 4: impacts severe at first, then weaker; finally continuous
  // contact; joint force peaks about 20x the ideal joint's (we require > 5x).
  const Scene sc = test::scene("paper_clearance");
  double early_peak = 0.0, late_peak = 0.0;
  const RunResult r = simulate(sc, [&](const Row& row) {
    (row.t < 0.5 ? early_peak : late_peak) = std::max(row.t < 0.5 ? early_peak : late_peak, row.fn2);
  });
  ASSERT_TRUE(r.ok) << r.error;
  const Scene sci = test::scene("paper_ideal");
  const RunResult ri = simulate(sci, [](const Row&) {});
  ASSERT_TRUE(ri.ok);
  EXPECT_GT(r.stats.impacts, 3);
  EXPECT_TRUE(r.in_contact_at_end);
  EXPECT_LT(r.stats.last_onset_time, 4.0) << "continuous contact should set in";
  EXPECT_GT(r.stats.peak_fn, late_peak);
  EXPECT_GT(r.peak_joint2_force, 5.0 * ri.peak_joint2_force);
}

}  // namespace
}  // namespace gimbalsim
