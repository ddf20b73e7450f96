// Fast subset of the numerical stability stress grid (issue 4), checked with
// the same classifier as build/bin/gimbalsim_stress (tools/stress/).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "../test_util.hpp"
#include "stress_check.hpp"
#include "stress_grid.hpp"

namespace gimbalsim::stress {
namespace {

using test::scene;
using test::scenePath;

/// Runs a grid case and prints what the tool prints about it.
Outcome run(const std::string& name, std::vector<std::string> sets, const std::string& duration = "0.5") {
  sets.insert(sets.begin(), "sim.duration=" + duration);
  const Outcome o = runCase(scenePath(name), sets, Bounds{});
  std::printf("%s: %s, momentum drift P %.3g L %.3g, energy rise %.3g, penetration %.3g m, %.3g sub-steps/s %s\n",
              name.c_str(), verdictName(o.verdict), o.momentum_rel_linear, o.momentum_rel_angular,
              o.energy_rise_rel, o.max_penetration, o.substeps_per_second, o.reason.c_str());
  return o;
}

#define EXPECT_TRUSTWORTHY(o) EXPECT_EQ((o).verdict, Verdict::Trustworthy) << (o).reason
#define EXPECT_STOPPED_ON(o, limit)                             \
  do {                                                          \
    EXPECT_EQ((o).verdict, Verdict::Stopped) << (o).reason;     \
    EXPECT_NE((o).reason.find(limit), std::string::npos) << (o).reason; \
  } while (0)

// ---- the classifier on fabricated runs ----

Row row(double t, double energy, double theta1, double theta2, double delta = 0.0) {
  Row r{};
  r.t = t;
  r.energy = energy;
  r.theta1 = theta1;
  r.theta2 = theta2;
  r.delta2 = delta;
  r.base_vx = 1e-3;  // 1 kg m/s of base momentum with the paper's 1000 kg base
  return r;
}

TEST(StressClassifier, TorqueWorkAndHertzEnergyAreNotARise) {
  // tau = (5, 10) N m: turning joint 1 by 0.2 rad and joint 2 by 0.1 rad does
  // 2 J of work, which the kinetic energy may gain; energy moved into the
  // Hertz spring is not a loss either.
  const Scene sc = scene("paper_clearance");
  const Model& m = sc.model;
  EnergyMonitor e(m, sc.run.torque);
  e.feed(row(0.0, 1.0, 0.0, 0.0), 0.0);
  e.feed(row(0.1, 3.0, 0.2, 0.1), 0.0);
  const double delta = 1e-5, U = m.bearing[1].K * std::pow(delta, 2.5) / 2.5;
  e.feed(row(0.2, 3.0 - U, 0.2, 0.1, delta), U);  // the spring's energy, from the state
  EXPECT_LT(e.maxRise(), 1e-12);
  EXPECT_NEAR(e.scale(), 3.0, 1e-12);
  e.feed(row(0.3, 3.5, 0.2, 0.1), 0.0);  // 0.5 J from nowhere
  EXPECT_NEAR(e.maxRise(), 0.5, 1e-12);
  // Falling, then rising back to below the earlier maximum is still a rise.
  e.feed(row(0.4, 2.0, 0.2, 0.1), 0.0);
  e.feed(row(0.5, 2.1, 0.2, 0.1), 0.0);
  EXPECT_NEAR(e.maxRise(), 0.5, 1e-12);
  EnergyMonitor f(m, sc.run.torque);
  f.feed(row(0.0, 1.0, 0.0, 0.0), 0.0);
  f.feed(row(0.1, 0.5, 0.0, 0.0), 0.0);
  f.feed(row(0.2, 0.6, 0.0, 0.0), 0.0);
  EXPECT_NEAR(f.maxRise(), 0.1, 1e-12);
}

TEST(StressClassifier, VerdictsOfFabricatedRuns) {
  const Scene sc = scene("paper_clearance", {"sim.duration=0.2"});
  const Model& m = sc.model;
  EnergyMonitor e(m, sc.run.torque);
  e.feed(row(0.0, 1.0, 0.0, 0.0), 0.0);
  e.feed(row(0.2, 0.9, 0.0, 0.0), 0.0);
  RunResult r;
  r.ok = true;
  r.t_end = 0.2;
  r.momentum_scale = 10.0;
  r.max_drift_angular = 1e-12;
  r.final_q = {0.0, 1.0};
  r.final_v = {0.0};
  EXPECT_EQ(classify(sc, r, e, Bounds{}).verdict, Verdict::Trustworthy);
  r.max_drift_angular = 1e-6;  // 1e-7 of the scale
  Outcome o = classify(sc, r, e, Bounds{});
  EXPECT_EQ(o.verdict, Verdict::SilentlyWrong);
  EXPECT_NE(o.reason.find("angular momentum drift 1e-07"), std::string::npos) << o.reason;
  r.max_drift_angular = 0.0;
  r.max_drift_linear = 1e-6;  // of 2 N s (twice the base's momentum)
  EXPECT_EQ(classify(sc, r, e, Bounds{}).verdict, Verdict::SilentlyWrong);
  r.max_drift_linear = 0.0;
  r.final_v = {std::nan("")};
  EXPECT_EQ(classify(sc, r, e, Bounds{}).verdict, Verdict::SilentlyWrong);
  r.final_v = {0.0};
  r.t_end = 0.1;  // "ok" but short
  EXPECT_EQ(classify(sc, r, e, Bounds{}).verdict, Verdict::SilentlyWrong);
  r.stats.max_penetration = 2.0 * m.bearing[1].clearance;
  r.t_end = 0.2;
  EXPECT_EQ(classify(sc, r, e, Bounds{}).verdict, Verdict::SilentlyWrong);
  r.stats.max_penetration = 0.0;
  r.ok = false;
  const StepResult diverged{StepStatus::VelocityLimit, 0.1, -1, 7};
  r.stop = RunStop{RunStop::Kind::Step, diverged, diverged.key(), 0.1};
  EXPECT_EQ(classify(sc, r, e, Bounds{}).verdict, Verdict::Stopped);
  r.stop = RunStop{RunStop::Kind::Step, StepResult{StepStatus::NonFinite, 0.1, 3}, "", 0.1};
  EXPECT_EQ(classify(sc, r, e, Bounds{}).verdict, Verdict::Stopped);
  r.stop = RunStop{RunStop::Kind::Reference, {}, "", 0.1};  // gave up without naming a limit
  EXPECT_EQ(classify(sc, r, e, Bounds{}).verdict, Verdict::StoppedUnclear);
  // Conservative scene: the balance must be held, a 10 % loss is wrong.
  const Scene scc = scene("paper_clearance", {"sim.duration=0.2", "contact.damping=none", "friction.law=none"});
  ASSERT_TRUE(conservative(scc.model));
  ASSERT_FALSE(conservative(m));
  r.ok = true;
  r.error.clear();
  EXPECT_EQ(classify(scc, r, e, Bounds{}).verdict, Verdict::SilentlyWrong);
}

// ---- a fast subset of the grid ----

// (pass 49) --long-set sim.duration=60 listed the hour's sim.duration=3600 too, on the page and in the CSV.
TEST(StressGrid, ALongSetKeyReplacesTheHoursOwn) {
  const std::vector<std::string> sets = longCase("paper_clearance", {"sim.duration=60", "friction.law=none"}).sets;
  EXPECT_EQ(sets, (std::vector<std::string>{"sim.output_interval=0.01", "sim.duration=60", "friction.law=none"}));
  const std::vector<std::string> own = longCase("paper_clearance", {"friction.law=none"}).sets;
  EXPECT_EQ(own, (std::vector<std::string>{"sim.duration=3600", "sim.output_interval=0.01", "friction.law=none"}));
  // (pass 50) a key given twice was listed twice; an error named "--set #3", a place the user never wrote
  const auto twice = longSets({"sim.duration=0.5", "friction.law=none", "sim.duration=0.3"});
  ASSERT_EQ(twice.size(), 3u);
  EXPECT_EQ(twice[0].first, "sim.output_interval=0.01");
  EXPECT_EQ(twice[0].second, "the long run's own 'sim.output_interval=0.01'");
  EXPECT_EQ(twice[1].second, "--long-set #2 'friction.law=none'");
  EXPECT_EQ(twice[2].first, "sim.duration=0.3");
  EXPECT_EQ(twice[2].second, "--long-set #3 'sim.duration=0.3'");
}

TEST(StressGrid, PaperSceneTrustworthyAtDefaults) {
  EXPECT_TRUSTWORTHY(run("paper_clearance", {}));
  EXPECT_TRUSTWORTHY(run("planar_clearance", {"friction.law=ambrosio"}));
  EXPECT_TRUSTWORTHY(run("paper_clearance", {"structure.base=fixed"}));
}

TEST(StressGrid, ExtremeClearancesTrustworthyAtDefaultSubstep) {
  const Outcome small = run("paper_clearance", {"contact.clearance=5e-6"});
  EXPECT_TRUSTWORTHY(small);
  EXPECT_GT(small.run.stats.impacts, 3);
  EXPECT_TRUSTWORTHY(run("paper_clearance", {"contact.clearance=5e-3"}));
}

TEST(StressGrid, StiffContactWithControlPeriodSubstepStopsNamingTheLimit) {
  // x100 stiffness, sub-step = the 1 ms control period: far too coarse for
  // the contact (an impact lasts ~0.24 ms); the run must stop at the first
  // impact and say so, not finish wrong.
  for (const char* h : {"sim.substep=1e-3", "sim.substep=5e-4"}) {
    const Outcome o = run("paper_clearance", {"contact.stiffness_scale=100", h});
    EXPECT_STOPPED_ON(o, "sim.min_substeps_per_impact");
    EXPECT_EQ(o.run.stats.impacts, 1) << "stops at the first impact";
  }
  // The default sub-step resolves the same impacts (~12 sub-steps each).
  EXPECT_TRUSTWORTHY(run("paper_clearance", {"contact.stiffness_scale=100"}));
}

TEST(StressGrid, ARunStoppedInItsFirstStepHasNoRateDriftOrEnergyFigure) {
  // (pass 82) sub-steps/s, drifts and energy figures of a run that completed no step were 0, read as "held"
  const Outcome o = run("paper_clearance", {"sim.velocity_limit=1e-300"}, "0.01");
  EXPECT_STOPPED_ON(o, "sim.velocity_limit");
  ASSERT_EQ(o.run.t_end, 0.0);
  for (double figure : {o.substeps_per_second, o.momentum_rel_linear, o.momentum_rel_angular, o.energy_rise_rel,
                        o.energy_change_rel, o.energy_final_rel}) {
    EXPECT_TRUE(std::isnan(figure)) << figure;
  }
  EXPECT_NE(o.reason.find("no sub-step rate, momentum drift or energy figure: the run stopped in its first step"),
            std::string::npos)
      << o.reason;
  EXPECT_EQ(o.max_penetration, 0.0) << "the initial state's, seen";
  const Outcome ok = run("paper_clearance", {}, "0.01");  // a run that stepped keeps its figures
  EXPECT_GT(ok.substeps_per_second, 0.0);
  EXPECT_LE(ok.momentum_rel_angular, 1e-9);
}

TEST(StressGrid, SoftContactUnderLargeTorqueStopsOnPenetration) {
  // x0.01 stiffness, x20 torques: the journal sinks deeper than the clearance.
  EXPECT_STOPPED_ON(run("paper_clearance", {"contact.stiffness_scale=0.01", "torque.tau1=100", "torque.tau2=200"}),
                    "sim.penetration_limit");
}

TEST(StressGrid, SoftContactTrustworthyWithLargeSubstep) {
  // x0.01 stiffness: the contact lasts long enough for 0.1 ms sub-steps (at
  // 0.2 ms the momentum drifts by 1.2e-9 of its scale early in the run and
  // the guard sim.momentum_tol stops it).
  EXPECT_TRUSTWORTHY(run("paper_clearance", {"contact.stiffness_scale=0.01", "sim.substep=1e-4"}));
  EXPECT_STOPPED_ON(run("paper_clearance", {"contact.stiffness_scale=0.01", "sim.substep=2e-4"}),
                    "sim.momentum_tol");
}

TEST(StressGrid, EnergyOnlyFallsUnderDampingAndFriction) {
  for (const char* law : {"coulomb", "ambrosio"}) {
    const Outcome o = run("paper_clearance", {"torque.tau1=0", "torque.tau2=0", "initial.dtheta1=1.0",
                                              "initial.dtheta2=-0.5", "contact.restitution=0.7",
                                              std::string("friction.law=") + law});
    EXPECT_TRUSTWORTHY(o);
    EXPECT_GT(o.run.stats.impacts, 5);
    EXPECT_LT(o.energy_final_rel, -1e-3) << "impacts and friction must take energy out";
  }
}

TEST(StressGrid, EnergyHeldWithoutDampingOrFriction) {
  const Outcome o = run("paper_clearance", {"contact.damping=none", "friction.law=none"});
  EXPECT_TRUSTWORTHY(o);
  EXPECT_GT(o.run.stats.impacts, 5);
}

TEST(StressGrid, EnergyHeldWithPlanarPlayInBothJoints) {
  // Both springs in the balance: joint 1's from the row's delta1, joint 2's
  // from its delta (rowHertzEnergy). Leaving either out breaks it at impact.
  const Outcome o = run("paper_both_planar", {"contact.damping=none", "friction.law=none"});
  EXPECT_TRUSTWORTHY(o);
  EXPECT_GT(o.run.stats.impacts_joint[0], 2);
  EXPECT_GT(o.run.stats.impacts_joint[1], 2);
}

TEST(StressGrid, EveryJointKindTrustworthyOrStoppedNamingTheLimit) {
  // At the grid's momentum bound (1e-9, as the run's own sim.momentum_tol)
  // no run may finish wrong. Where it can hold that bound it must: with no
  // friction or the smooth law and no spatial joint 1. Plain Coulomb's
  // chatter breaks it in planar_spatial2; a spatial joint 1 breaks it in
  // the first milliseconds, when the momenta are still tiny (the reason
  // paper_spatial1 and paper_both_spatial ship with sim.momentum_tol 1e-5).
  for (const char* name : {"paper_planar1", "paper_both_planar", "paper_spatial2", "paper_spatial1",
                           "paper_both_spatial", "planar_spatial2"}) {
    for (const char* law : {"none", "ambrosio", "coulomb"}) {
      const Outcome o = run(name, {"sim.momentum_tol=1e-9", std::string("friction.law=") + law}, "0.3");
      EXPECT_TRUE(acceptable(o.verdict)) << name << " " << law << ": " << verdictName(o.verdict) << " " << o.reason;
      if (o.verdict == Verdict::Stopped) {
        EXPECT_EQ(o.run.stop.key, std::string("sim.momentum_tol")) << name << " " << law;
      }
      const bool spatial1 = test::scene(name).model.joint1_kind == ClearanceKind::Spatial;
      if (std::string(law) != "coulomb" && !spatial1) {
        EXPECT_TRUSTWORTHY(o) << name << " " << law;
        EXPECT_GT(o.run.stats.impacts, 0) << name << " " << law;
      }
    }
  }
}

TEST(StressGrid, IdealScenesTrustworthyAtControlPeriod) {
  // The paper's torques; at x20 torques the rates are 20 times higher and a
  // 1 ms step leaves ~2e-8 relative momentum drift (the tool lists that case).
  for (const char* name : {"paper_ideal", "planar_ideal"}) {
    EXPECT_TRUSTWORTHY(run(name, {"sim.step=1e-3"}, "1"));
  }
}

TEST(StressGrid, StrongTorqueWithEachFrictionLaw) {
  for (const char* law : {"none", "ambrosio", "coulomb"}) {
    EXPECT_TRUSTWORTHY(run("paper_clearance", {"torque.tau1=100", "torque.tau2=200",
                                               std::string("friction.law=") + law}, "0.3"));
  }
}

TEST(StressGrid, AdaptivePolicyTrustworthyOrRefused) {
  // Error-controlled sub-steps: trustworthy at 1e-8 with the smooth friction
  // laws; plain Coulomb's sign flip defeats error control (every run stopped
  // on the sub-step cap), so the scene refuses that pair before it runs.
  for (const char* law : {"ambrosio", "coulomb_stick"}) {
    EXPECT_TRUSTWORTHY(run("paper_clearance", {"sim.substep_policy=adaptive", "sim.substep_tol=1e-8",
                                               std::string("friction.law=") + law}));
  }
  EXPECT_THROW(test::scene("paper_clearance", {"sim.substep_policy=adaptive", "friction.law=coulomb"}), SceneError);
}

// ---- cases the tool found SILENTLY_WRONG before the integrator learnt to see them ----
// Each used to finish "ok" while the energy balance rose: an impact that
// begins and ends inside one RK4 sub-step (both end points out of contact, so
// no switch was located, and the stages applied a force with a stale v0), or
// a sub-step much longer than the contact.

TEST(StressGrid, ImpactInsideOnePlainStepIsLocated) {
  // x100 stiffness, 5 um clearance, default sub-step: the journal creeps
  // towards the bearing (gap rate ~1e-4 m/s, gap ~1e-7 m), the linear gap
  // predictor takes a plain 1 ms step, and the journal bounces inside it.
  // The sub-step is retaken shorter until the contact shows at its end.
  const Outcome o = run("paper_clearance", {"contact.stiffness_scale=100", "contact.clearance=5e-6"});
  EXPECT_TRUSTWORTHY(o);
  EXPECT_GT(o.run.stats.straddle_retries, 0);
  EXPECT_GT(o.run.stats.impacts, 0);
}

TEST(StressGrid, StiffDampedImpactInsideTheRemainderOfAStep) {
  // The first impact (~12 sub-steps of 2e-5 s) drifts the momentum by
  // 1.02e-9 of the scale it has at 0.032 s, which the run-time guard at its
  // default 1e-9 would stop; at 1e-8 the run goes on, and the classifier
  // still holds the drift to 1e-9 of the whole run's scale.
  const Outcome o = run("paper_clearance", {"contact.stiffness_scale=100", "contact.damping=flores",
                                            "contact.restitution=0.3", "sim.momentum_tol=1e-8"});
  EXPECT_TRUSTWORTHY(o);
  EXPECT_GT(o.run.stats.straddle_retries, 0);
}

TEST(StressGrid, ControlPeriodSubstepAtLargeClearance) {
  // 5 mm clearance: impacts at higher speed last ~1.3 ms, one 1 ms sub-step.
  const Outcome o = run("paper_clearance", {"contact.clearance=5e-3", "sim.substep=1e-3"});
  EXPECT_STOPPED_ON(o, "sim.min_substeps_per_impact");
  // With that check and the invariant guards off, the same run finishes
  // silently wrong: the checks are what stand between the user and it.
  const Outcome off = run("paper_clearance", {"contact.clearance=5e-3", "sim.substep=1e-3",
                                              "sim.min_substeps_per_impact=0", "sim.momentum_tol=0",
                                              "sim.energy_tol=0"});
  EXPECT_EQ(off.verdict, Verdict::SilentlyWrong) << off.reason;
}

// ---- restitution of the damping laws ----

double restitution(const std::string& law, double ce, double v_in) {
  const Model m = test::model("paper_clearance", {"structure.base=fixed", "friction.law=none", "torque.tau1=0",
                                                  "torque.tau2=0", "sim.substep=1e-6", "sim.event_tol=1e-12",
                                                  "contact.damping=" + law, "contact.restitution=" + std::to_string(ce)});
  return effectiveRestitution(m, v_in);
}

TEST(StressRestitution, FloresHoldsTheRequestedRestitutionLankaraniNikraveshDoesNot) {
  // Lankarani-Nikravesh (and Hunt-Crossley) are derived for c_e near 1: at
  // c_e = 0.3 they dissipate far too little; Flores et al. 2011 holds c_e
  // over the whole range.
  for (double ce : {0.3, 0.5, 0.7, 0.9}) {
    const double flores = restitution("flores", ce, 0.05);
    const double ln = restitution("lankarani_nikravesh", ce, 0.05);
    const double hc = restitution("hunt_crossley", ce, 0.05);
    std::printf("c_e %.2f: flores %.4f, lankarani_nikravesh %.4f, hunt_crossley %.4f\n", ce, flores, ln, hc);
    EXPECT_NEAR(flores, ce, 0.05);
    EXPECT_LT(std::fabs(flores - ce), std::fabs(ln - ce));
    EXPECT_LT(std::fabs(flores - ce), std::fabs(hc - ce));
  }
  EXPECT_GT(restitution("lankarani_nikravesh", 0.3, 0.05), 0.6);
  for (const char* law : {"flores", "lankarani_nikravesh", "hunt_crossley"}) {
    EXPECT_NEAR(restitution(law, 1.0, 0.05), 1.0, 1e-6) << law;
  }
}

TEST(StressRestitution, IndependentOfImpactVelocity) {
  // D = chi K delta^n / v0 makes the restitution a function of chi alone.
  for (const char* law : {"flores", "lankarani_nikravesh"}) {
    const double slow = restitution(law, 0.5, 0.01), fast = restitution(law, 0.5, 0.2);
    EXPECT_NEAR(slow, fast, 2e-3) << law;
  }
}

}  // namespace
}  // namespace gimbalsim::stress
