#include "gimbalsim/dynamics/invariants.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "gimbalsim/dynamics/simulate.hpp"

namespace gimbalsim {

bool conservative(const Model& m) {
  const auto undamped = [](const ContactParams& c) { return c.damping == DampingLaw::None || c.chi == 0.0; };
  const bool no_damping = (m.joint1_kind == ClearanceKind::Ideal || undamped(m.bearing[0])) &&
                          (m.joint2_kind == ClearanceKind::Ideal || undamped(m.bearing[1]));
  return !m.hasClearance() || (no_damping && !frictionActive(m));
}

bool energyBalanceHeld(const Model& m) {
  return m.joint1_kind != ClearanceKind::Spatial && m.joint2_kind != ClearanceKind::Spatial;
}

InvariantMonitor::InvariantMonitor(const Model& m, const Vec2& torque)
    : m_(m), torque_(torque), conservative_(conservative(m)), energy_checked_(energyBalanceHeld(m)),
      reach_(m.r_J1_B_B.norm() + std::max(m.shaft1.com.norm(), m.r_J2_S1_S1.norm() + m.shaft2.com.norm())) {}

double InvariantMonitor::relative(double x, double scale) {
  if (x == 0.0) return 0.0;
  return scale > 0.0 ? x / scale : std::numeric_limits<double>::infinity();
}

void InvariantMonitor::feed(const Row& r, double hertz_energy, double angular_scale, double linear_scale) {
  finite_ = finite_ && rowFinite(r);
  const double U = hertz_energy;
  if (rows_ == 0) {
    theta1_0_ = r.theta1;
    theta2_0_ = r.theta2;
  }
  const double W = torque_(0) * (r.theta1 - theta1_0_) + torque_(1) * (r.theta2 - theta2_0_);
  const double B = r.energy + U - W;
  const double P[3] = {r.mom_px, r.mom_py, r.mom_pz}, L[3] = {r.mom_lx, r.mom_ly, r.mom_lz};
  if (rows_ == 0) {
    b0_ = b_min_ = B;
    p0_ = std::sqrt(P[0] * P[0] + P[1] * P[1] + P[2] * P[2]);
    std::copy(P, P + 3, P0_);
    std::copy(L, L + 3, L0_);
  } else {
    max_rise_ = std::max(max_rise_, B - b_min_);
    b_min_ = std::min(b_min_, B);
  }
  max_change_ = std::max(max_change_, std::fabs(B - b0_));
  b_last_ = B;
  scale_ = std::max({scale_, r.energy + U, std::fabs(W)});
  const double vb = std::sqrt(r.base_vx * r.base_vx + r.base_vy * r.base_vy + r.base_vz * r.base_vz);
  // The chain carries P - p_base, so sum_i |p_i| >= |p_base| + |P - p_base|
  // >= 2 |p_base| - |P|: a lower bound of the bodies' momentum sum.
  // Bodies turning about their own centres of mass carry sum |p_i| at round-off (7e-16 N s in a spatial
  // scene's first millisecond) while their angular momentum is not: P is judged against L at the chain's reach.
  const double from_angular = reach_ > 0.0 ? angular_scale / reach_ : 0.0;
  lin_scale_ = std::max({lin_scale_, p0_ + 2.0 * m_.base.mass * vb, linear_scale, from_angular});
  ang_scale_ = std::max(ang_scale_, angular_scale);
  drift_lin_ = std::max(drift_lin_, std::hypot(P[0] - P0_[0], P[1] - P0_[1], P[2] - P0_[2]));
  drift_ang_ = std::max(drift_ang_, std::hypot(L[0] - L0_[0], L[1] - L0_[1], L[2] - L0_[2]));
  max_delta_ = std::max({max_delta_, r.delta1, r.delta2});  // either joint's
  ++rows_;
}

InvariantMonitor::Violation InvariantMonitor::violation() const {
  const IntegratorParams& p = m_.integrator;
  const bool chatter = m_.joint2_kind != ClearanceKind::Ideal && m_.bearing[1].friction == FrictionLaw::Coulomb &&
                       m_.bearing[1].mu > 0.0;
  auto say = [&](const char* what, double x, const char* key, double tol) {
    char num[64];
    std::snprintf(num, sizeof num, " %.3g of its scale, above ", x);
    std::string out = std::string(what) + num + key + " = ";
    std::snprintf(num, sizeof num, "%.3g", tol);
    out += std::string(num) +
           " (a step or sub-step too long for this accuracy: reduce sim.step / sim.substep, use "
           "sim.substep_policy=adaptive";
    if (chatter) out += ", or friction.law=coulomb_stick (plain Coulomb chatters where the journal sticks)";
    return Violation{key, out + ", or raise " + key + ")"};
  };
  if (m_.floating_base && p.momentum_tol > 0.0) {
    if (ang_scale_ > 0.0 && !(angularDriftRel() <= p.momentum_tol)) {
      return say("angular momentum drift", angularDriftRel(), "sim.momentum_tol", p.momentum_tol);
    }
    if (!(linearDriftRel() <= p.momentum_tol)) {
      return say("linear momentum drift", linearDriftRel(), "sim.momentum_tol", p.momentum_tol);
    }
  }
  if (p.energy_tol > 0.0 && energy_checked_) {
    if (!(energyRiseRel() <= p.energy_tol)) {
      return say("energy balance (kinetic + Hertz - torque work) rose by", energyRiseRel(), "sim.energy_tol",
                 p.energy_tol);
    }
    if (conservative_ && !(energyChangeRel() <= p.energy_tol)) {
      return say("conservative scene: energy balance changed by", energyChangeRel(), "sim.energy_tol",
                 p.energy_tol);
    }
  }
  return {};
}

}  // namespace gimbalsim
