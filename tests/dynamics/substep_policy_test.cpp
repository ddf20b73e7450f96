// The adaptive contact sub-stepping policy (sim.substep_policy adaptive) and
// the set-valued Coulomb law with located stick/slip (friction.law
// coulomb_stick): agreement with a fine fixed sub-step and with the
// independent reference, the cap, the stick closure, momentum through
// stick/slip switches.
#include <cmath>
#include <cstdio>

#include "gimbalsim/dynamics/reference_integrator.hpp"
#include "test_util.hpp"

namespace gimbalsim {
namespace {

using V = FloatingClearanceFriction;

struct PolicyRun {
  State<V> s;
  RunStats stats;
};

PolicyRun runScene(const Scene& sc, double T) {
  const Model& m = sc.model;
  Data<V> d(m);
  PolicyRun r{initialState<V>(sc.run.initial), {}};
  test::advance(m, d, r.s, std::llround(T / m.integrator.step), Input{sc.run.torque});
  r.stats = d.stats;
  return r;
}

// 0.3 s of paper_clearance holds 5 impacts (the first at 0.03 s).
constexpr double kT = 0.3;

Scene paper(const std::vector<std::string>& sets) { return test::scene("paper_clearance", sets); }

// Adaptive at tol 1e-12 agrees with the fixed policy at a fine sub-step
// (2.5e-6 s: within 1e-10 m / rad of the dopri5 reference here) to 7e-10 m of
// eccentricity and 1e-9 rad of boresight, for the smooth Ambrosio law and for
// coulomb_stick. (Measured: adaptive 1e-12 is ~3.5e-10 off; the default fixed
// 2e-5 s is ~1.5e-9 m / 2e-9 rad off and would fail these bounds.)
TEST(SubstepPolicy, AdaptiveAgreesWithFineFixedSubstep) {
  for (const char* law : {"friction.law=ambrosio", "friction.law=coulomb_stick"}) {
    const Scene fine = paper({law, "sim.substep=2.5e-6", "sim.event_tol=1e-11"});
    const Scene adapt = paper({law, "sim.substep_policy=adaptive", "sim.substep_tol=1e-12", "sim.event_tol=1e-11"});
    const PolicyRun a = runScene(fine, kT), b = runScene(adapt, kT);
    EXPECT_GE(a.stats.impacts, 4) << law;
    EXPECT_EQ(a.stats.impacts, b.stats.impacts) << law;
    const double err = test::angleBetween(test::boresightOf(fine.model, a.s), test::boresightOf(adapt.model, b.s));
    EXPECT_LT(err, 1e-9) << law;
    EXPECT_NEAR(a.s.q(State<V>::QJ + 1), b.s.q(State<V>::QJ + 1), 7e-10) << law << ": ecc_x [m]";
    EXPECT_NEAR(a.s.q(State<V>::QJ + 2), b.s.q(State<V>::QJ + 2), 7e-10) << law << ": ecc_y [m]";
    EXPECT_EQ(b.stats.forced_substeps, 0) << law;
  }
}

// A looser tolerance must give a larger error: the control is real.
TEST(SubstepPolicy, ToleranceControlsTheError) {
  const Scene fine = paper({"friction.law=ambrosio", "sim.substep=2.5e-6", "sim.event_tol=1e-11"});
  const PolicyRun ref = runScene(fine, kT);
  const Vec3 b_ref = test::boresightOf(fine.model, ref.s);
  double prev_err = 0.0;
  long long prev_n = 1LL << 60;
  for (const char* tol : {"sim.substep_tol=1e-7", "sim.substep_tol=1e-11"}) {
    const Scene sc = paper({"friction.law=ambrosio", "sim.substep_policy=adaptive", tol});
    const PolicyRun r = runScene(sc, kT);
    const double err = test::angleBetween(b_ref, test::boresightOf(sc.model, r.s));
    if (prev_err > 0.0) {
      EXPECT_LT(err, 0.5 * prev_err) << tol;
      EXPECT_GT(r.stats.substeps, prev_n) << tol;
    }
    prev_err = err;
    prev_n = r.stats.substeps;
  }
}

// Adaptive coulomb_stick against the independent reference (Dormand-Prince,
// same closure, switches located on its dense output): 1e-9 rad of boresight
// (measured ~4e-10).
TEST(SubstepPolicy, CoulombStickAdaptiveAgreesWithReference) {
  const Scene sc = paper({"friction.law=coulomb_stick", "sim.substep_policy=adaptive", "sim.substep_tol=1e-12",
                          "sim.event_tol=1e-11"});
  const Model& m = sc.model;
  const PolicyRun r = runScene(sc, kT);
  ReferenceIntegrator<V> ref(m, Input{sc.run.torque});
  State<V> s = initialState<V>(sc.run.initial);
  ASSERT_TRUE(ref.advanceTo(s, kT)) << ref.failure();
  EXPECT_EQ(ref.impacts(), r.stats.impacts);
  EXPECT_GT(ref.frictionSwitches(), 0);
  EXPECT_LT(test::angleBetween(test::boresightOf(m, s), test::boresightOf(m, r.s)), 1e-9);
}

// Every step is bounded: a cap below what the contact needs stops the run
// with SubstepCap and does not advance the state; with the automatic cap no
// step exceeds it and the step ends exactly on the grid.
TEST(SubstepPolicy, AdaptiveRespectsTheCapAndLandsOnTheGrid) {
  {
    const Scene sc = paper({"friction.law=coulomb_stick", "sim.substep_policy=adaptive", "sim.max_substeps=4"});
    const Model& m = sc.model;
    Data<V> d(m);
    State<V> s = initialState<V>(sc.run.initial);
    const Input u{sc.run.torque};
    StepResult st;
    long long before = 0;
    double t_grid = 0.0;
    for (int k = 0; k < 100 && st.ok(); ++k) {
      before = d.stats.substeps;
      t_grid = s.t;
      st = step(m, d, s, u);
    }
    EXPECT_EQ(st.status, StepStatus::SubstepCap);
    EXPECT_LE(d.stats.substeps - before, 4) << "the failing step took more than the cap";
    EXPECT_LT(st.time, t_grid + m.integrator.step);
  }
  const Scene sc = paper({"friction.law=coulomb_stick", "sim.substep_policy=adaptive", "sim.substep_tol=1e-12"});
  const Model& m = sc.model;
  Data<V> d(m);
  State<V> s = initialState<V>(sc.run.initial);
  const Input u{sc.run.torque};
  const double h = m.integrator.step;
  for (int k = 1; k <= 100; ++k) {
    ASSERT_EQ(step(m, d, s, u).status, StepStatus::Ok);
    ASSERT_NEAR(s.t, k * h, 1e-15 * k);
  }
  EXPECT_GT(d.stats.impacts, 0);
  EXPECT_LE(d.stats.max_substeps_in_step, substepCap(m));
  EXPECT_GT(d.stats.max_substeps_in_step, 1);
}

// A state in contact with the journal rolling (v_t = 0): put the contact at
// a given penetration with v_t zeroed through dtheta2.
State<V> rollingContactState(const Scene& sc, double delta) {
  const Model& m = sc.model;
  State<V> s = initialState<V>(sc.run.initial);
  constexpr int QJ = State<V>::QJ, NB = V::NB;
  s.q(QJ + 1) = m.bearing[1].clearance + delta;  // along u1
  s.v(NB) = 0.3;                               // dtheta1 [rad/s]
  s.v(NB + 2) = 0.01;                          // tangential journal slide [m/s]
  s.v.template head<3>() << 0.01, -0.02, 0.03;  // base rates [rad/s]
  s.v(NB + 3) = 0.0;
  s.v(NB + 3) = -tangentialVelocity<V>(m, s.q, s.v) / m.bearing[1].journal_radius;
  s.in_contact[0] = true;
  s.v0[0] = 0.01;
  s.friction_mode = 0;
  return s;
}

// In stick the closure's F_t makes dv_t/dt = 0: checked by differencing v_t
// along the flow (independent of the closure's analytic a0 and b), against
// the acceleration the same state has without friction.
TEST(CoulombStick, StickClosureHoldsTheTangentialVelocity) {
  const Scene sc = paper({"friction.law=coulomb_stick", "friction.mu=0.9"});
  const Model& m = sc.model;
  Data<V> d(m);
  const State<V> s = rollingContactState(sc, 2e-6);
  const Input u{sc.run.torque};
  ASSERT_NEAR(tangentialVelocity<V>(m, s.q, s.v), 0.0, 1e-15);
  auto vtRate = [&](const State<V>& x) {
    forwardDynamics(m, d, x, u);
    const auto qd = d.qdot;
    const auto vd = d.vdot;
    const double eps = 1e-7;
    State<V> p = x, q = x;
    p.q += eps * qd;
    p.v += eps * vd;
    q.q -= eps * qd;
    q.v -= eps * vd;
    return (tangentialVelocity<V>(m, p.q, p.v) - tangentialVelocity<V>(m, q.q, q.v)) / (2 * eps);
  };
  const double a_stick = vtRate(s);
  ASSERT_GT(d.contact[0].fn, 0.0);
  EXPECT_LT(std::fabs(d.contact[0].ft_required), m.bearing[1].mu * d.contact[0].fn) << "this state must stick";
  EXPECT_EQ(d.contact[0].ft, d.contact[0].ft_required);
  const Model free_m = paper({"friction.law=none"}).model;
  Data<FloatingClearance> df(free_m);
  State<FloatingClearance> sf;
  sf.q = s.q;
  sf.v = s.v;
  sf.in_contact[0] = true;
  sf.v0[0] = s.v0[0];
  forwardDynamics(free_m, df, sf, u);
  const double a_free = tangentialVelocity<FloatingClearance>(free_m, sf.q, df.vdot) +
                        tangentialVelocityRateAtFixedV<FloatingClearance>(free_m, sf.q, sf.v);
  EXPECT_GT(std::fabs(a_free), 1e-2) << "friction must have work to do";
  EXPECT_LT(std::fabs(a_stick), 1e-6 * std::fabs(a_free));
  EXPECT_EQ(consistentFrictionMode(m, d), 0);
}

// With too little friction the same state cannot stick: the force is clamped
// to mu F_n and the consistent mode is a slip in the direction v_t is driven.
TEST(CoulombStick, SlipsWhenStickingNeedsMoreThanMuFn) {
  const Scene sc = paper({"friction.law=coulomb_stick", "friction.mu=0.9"});
  const Model& m = sc.model;
  Data<V> d(m);
  const State<V> s = rollingContactState(sc, 2e-6);
  forwardDynamics(m, d, s, Input{sc.run.torque});
  const double needed = std::fabs(d.contact[0].ft_required);
  const double fn = d.contact[0].fn;
  ASSERT_GT(needed, 0.0);
  // A mu just below what sticking needs.
  const double mu_low = 0.5 * needed / fn;
  char mu_set[64];
  std::snprintf(mu_set, sizeof mu_set, "friction.mu=%.17g", mu_low);
  const Scene weak_sc = paper({"friction.law=coulomb_stick", mu_set});
  const Model& weak = weak_sc.model;
  const Input u_weak{weak_sc.run.torque};
  forwardDynamics(weak, d, s, u_weak);
  EXPECT_NEAR(std::fabs(d.contact[0].ft), mu_low * fn, 1e-9 * fn);
  const int mode = consistentFrictionMode(weak, d);
  ASSERT_NE(mode, 0);
  // Slipping in that mode drives v_t away from 0 in its direction.
  State<V> slip = s;
  slip.friction_mode = mode;
  forwardDynamics(weak, d, slip, u_weak);
  const double a = tangentialVelocity<V>(weak, slip.q, d.vdot) + tangentialVelocityRateAtFixedV<V>(weak, slip.q, slip.v);
  EXPECT_GT(mode * a, 0.0);
}

// Momentum is held through impacts, v_t reversals and stick/slip switches,
// and stick really happens in the window (fixed and adaptive policies).
TEST(CoulombStick, MomentumHeldThroughStickSlipSwitches) {
  for (const char* pol : {"sim.substep_policy=fixed", "sim.substep_policy=adaptive"}) {
    const Scene sc = paper({"friction.law=coulomb_stick", pol, "sim.substep_tol=1e-11"});
    const Model& m = sc.model;
    Data<V> d(m);
    State<V> s = initialState<V>(sc.run.initial);
    const Input u{sc.run.torque};
    kinematics(m, d, s.q, s.v);
    const Momentum p0 = momentum(m, d, s);
    double max_dp = 0.0, max_dl = 0.0, stick_time = 0.0;
    for (int k = 0; k < 500; ++k) {
      ASSERT_EQ(step(m, d, s, u).status, StepStatus::Ok) << pol;
      if (s.in_contact[0] && s.friction_mode == 0) stick_time += m.integrator.step;
      kinematics(m, d, s.q, s.v);
      const Momentum p = momentum(m, d, s);
      max_dp = std::max(max_dp, (p.linear - p0.linear).norm());
      max_dl = std::max(max_dl, (p.angular - p0.angular).norm());
    }
    EXPECT_GT(d.stats.friction_switches, 3) << pol;
    EXPECT_GT(stick_time, 0.0) << pol;
    EXPECT_LT(max_dp, 1e-9) << pol << " [N s]";
    EXPECT_LT(max_dl, 1e-9) << pol << " [N m s]";
  }
}

}  // namespace
}  // namespace gimbalsim
