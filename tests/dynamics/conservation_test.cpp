// Invariants any correct run satisfies (docs/MODEL.md section 8.7).
#include <gtest/gtest.h>

#include "test_util.hpp"

namespace gimbalsim {
namespace {

using test::momentumOf;

/// Linear and angular momentum held through impacts and friction.
template <class V>
void checkMomentum(const Scene& sc, double T, bool expect_impacts, double rel_tol = 1e-12) {
  const Model& m = sc.model;
  const Input u{sc.run.torque};
  Data<V> d(m);
  State<V> s = initialState<V>(sc.run.initial);
  const Momentum h0 = momentumOf(m, s);
  double worst_lin = 0.0, worst_ang = 0.0, scale = h0.scale;
  double lin_scale = 0.0;
  const long long n = std::llround(T / m.integrator.step);
  for (long long k = 0; k < n; ++k) {
    ASSERT_EQ(step(m, d, s, u).status, StepStatus::Ok) << "t = " << s.t;
    const Momentum h = momentumOf(m, s);
    scale = std::max(scale, h.scale);
    worst_lin = std::max(worst_lin, (h.linear - h0.linear).norm());
    worst_ang = std::max(worst_ang, (h.angular - h0.angular).norm());
    lin_scale = std::max(lin_scale, h.scale_linear);
  }
  if (expect_impacts) EXPECT_GT(d.stats.impacts, 0) << "the window must contain impacts";
  ASSERT_GT(scale, 1.0);
  std::printf("momentum drift: linear %.3g (relative %.3g), angular %.3g (relative %.3g)\n", worst_lin,
              worst_lin / lin_scale, worst_ang, worst_ang / scale);
  EXPECT_LT(worst_ang / scale, rel_tol) << "angular momentum drift " << worst_ang << " N m s of " << scale;
  EXPECT_LT(worst_lin / lin_scale, rel_tol) << "linear momentum drift " << worst_lin << " N s of " << lin_scale;
}

TEST(Conservation, MomentumHeldThroughImpactsAndFriction) {
  // The contact force is internal, so d(momentum)/dt = 0 exactly; what RK4
  // leaves is truncation error where the right-hand side is not smooth
  // (Coulomb's sign flip, the onset of Hertz contact): it falls as h^2.
  const Scene sc = test::scene("paper_clearance", {"sim.substep=1e-5"});
  ASSERT_EQ(sc.model.bearing[1].friction, FrictionLaw::Coulomb);
  checkMomentum<FloatingClearanceFriction>(sc, 0.3, true, 1e-10);
}

TEST(Conservation, MomentumHeldFromNonZeroInitialMomentum) {
  const Scene sc = test::scene("paper_clearance", {"initial.dtheta1=0.7", "initial.dtheta2=-0.4",
                                                   "initial.ecc2=[1.0e-4, -2.0e-4]", "friction.law=ambrosio",
                                                   "sim.substep=1e-5"});
  checkMomentum<FloatingClearanceFriction>(sc, 0.3, true, 1e-12);
  const Scene sci = test::scene("paper_ideal", {"initial.dtheta1=0.7", "initial.dtheta2=-0.4"});
  checkMomentum<FloatingIdeal>(sci, 1.0, false);
  const Scene scp = test::scene("planar_clearance", {"initial.dtheta1=0.7", "friction.law=ambrosio", "sim.substep=1e-5"});
  checkMomentum<FloatingClearanceFriction>(scp, 0.3, true, 1e-10);
}

/// Momentum rate along the exact flow: (P(s + eps sdot) - P(s - eps sdot)) / 2 eps.
template <class V>
std::pair<Vec3, Vec3> momentumRate(const Model& m, const State<V>& s, const Input& u) {
  Data<V> d(m);
  forwardDynamics(m, d, s, u);
  const auto qd = d.qdot;
  const auto vd = d.vdot;
  const double eps = 1e-7;
  State<V> a = s, b = s;
  a.q += eps * qd, a.v += eps * vd;
  b.q -= eps * qd, b.v -= eps * vd;
  const Momentum ha = momentumOf(m, a), hb = momentumOf(m, b);
  return {(ha.linear - hb.linear) / (2 * eps), (ha.angular - hb.angular) / (2 * eps)};
}

TEST(Conservation, ContactAndFrictionExertNoNetForceOrMoment) {
  // Instantaneous check, no integrator: in deep contact with sliding friction
  // the momentum rate is zero to round-off, while the contact force is large.
  for (const char* name : {"paper_clearance", "planar_clearance"}) {
    const Scene sc = test::scene(name, {"friction.law=coulomb", "friction.mu=0.3"});
    const Model& m = sc.model;
    const Input u{sc.run.torque};
    State<FloatingClearanceFriction> s = initialState<FloatingClearanceFriction>(sc.run.initial);
    s.q(7) = 0.3, s.q(10) = -0.2;  // joint angles
    s.v << 0.1, -0.2, 0.3, 0.01, -0.02, 0.03, 0.5, 0.0, 0.0, -0.7;
    const double c = m.bearing[1].clearance;
    s.q(8) = 0.6 * (c + 2e-6), s.q(9) = 0.8 * (c + 2e-6);  // 2 um penetration
    s.v(7) = 0.6 * 0.01, s.v(8) = 0.8 * 0.01;              // approaching at 1 cm/s
    s.v0[0] = 0.01;
    s.in_contact[0] = true;
    Data<FloatingClearanceFriction> d(m);
    forwardDynamics(m, d, s, u);
    ASSERT_GT(d.contact[0].fn, 10.0);
    ASSERT_NE(d.contact[0].ft, 0.0);
    const auto [dP, dL] = momentumRate(m, s, u);
    const double F = std::hypot(d.contact[0].fn, d.contact[0].ft);
    EXPECT_LT(dP.norm(), 1e-7 * F) << name << ": dP/dt = " << dP.transpose() << " with |F| = " << F;
    EXPECT_LT(dL.norm(), 1e-7 * F) << name << ": dL/dt = " << dL.transpose();
  }
}

/// Kinetic energy plus stored Hertz energy minus the work of the joint
/// torques (a constant couple: W = tau1 dtheta1 + tau2 dtheta2).
template <class V>
double energyBalance(const Model& m, const Vec2& torque, const State<V>& s, double E0, const State<V>& s0) {
  double E = momentumOf(m, s).energy;
  if constexpr (V::kContact) {
    const double delta = clearanceGap<V>(m, s.q, s.v).delta;
    if (delta > 0) E += m.bearing[1].K * std::pow(delta, m.bearing[1].exponent + 1) / (m.bearing[1].exponent + 1);
  }
  const double W = torque(0) * (s.theta(0) - s0.theta(0)) + torque(1) * (s.theta(1) - s0.theta(1));
  return E - E0 - W;
}

template <class V>
void checkEnergy(const Scene& sc, double T, double rel_tol) {
  const Model& m = sc.model;
  const Input u{sc.run.torque};
  Data<V> d(m);
  State<V> s = initialState<V>(sc.run.initial);
  const State<V> s0 = s;
  const double E0 = momentumOf(m, s).energy;
  double worst = 0.0, work_scale = 1e-12;
  const long long n = std::llround(T / m.integrator.step);
  for (long long k = 0; k < n; ++k) {
    ASSERT_EQ(step(m, d, s, u).status, StepStatus::Ok);
    worst = std::max(worst, std::fabs(energyBalance(m, sc.run.torque, s, E0, s0)));
    work_scale = std::max(work_scale, momentumOf(m, s).energy);
  }
  if constexpr (V::kContact) EXPECT_GT(d.stats.impacts, 3);
  EXPECT_LT(worst / work_scale, rel_tol) << "energy imbalance " << worst << " J of " << work_scale << " J";
}

TEST(Conservation, EnergyEqualsTorqueWorkWithoutDampingOrFriction) {
  checkEnergy<FloatingIdeal>(test::scene("paper_ideal"), 2.0, 1e-9);
  checkEnergy<FloatingClearance>(
      test::scene("paper_clearance", {"contact.damping=none", "friction.law=none", "sim.substep=1e-5"}), 0.5,
      1e-6);
  checkEnergy<FixedClearance>(test::scene("paper_clearance", {"structure.base=fixed", "contact.restitution=1.0",
                                                              "friction.law=none", "sim.substep=1e-5"}),
                              0.5, 1e-6);
}

TEST(Conservation, EnergyNeverRisesUnderDissipation) {
  // No torque, moving joints: impacts with damping and friction only take energy out.
  const Scene sc = test::scene("paper_clearance", {"torque.tau1=0", "torque.tau2=0", "initial.dtheta1=1.0",
                                                   "initial.dtheta2=-0.5", "contact.restitution=0.7",
                                                   "friction.law=coulomb"});
  const Model& m = sc.model;
  const Input u{sc.run.torque};
  Data<FloatingClearanceFriction> d(m);
  State<FloatingClearanceFriction> s = initialState<FloatingClearanceFriction>(sc.run.initial);
  const double E0 = momentumOf(m, s).energy;
  double prev = E0, worst_rise = 0.0;
  for (int k = 0; k < 500; ++k) {
    ASSERT_EQ(step(m, d, s, u).status, StepStatus::Ok);
    double E = momentumOf(m, s).energy;
    const double delta = clearanceGap<FloatingClearanceFriction>(m, s.q, s.v).delta;
    if (delta > 0) E += m.bearing[1].K * std::pow(delta, 2.5) / 2.5;
    worst_rise = std::max(worst_rise, E - prev);
    prev = E;
  }
  EXPECT_GT(d.stats.impacts, 0);
  EXPECT_LT(prev, E0 * (1 - 1e-6)) << "impacts must dissipate";
  EXPECT_LT(worst_rise, 1e-9 * E0) << "energy rose by " << worst_rise << " J";
}

}  // namespace
}  // namespace gimbalsim
