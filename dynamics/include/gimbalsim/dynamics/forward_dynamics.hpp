// Forward dynamics: vdot = M(q)^-1 (tau + Q_contact - C(q, v)), with M from
// the CRBA, C from the RNEA, M^-1 by mass_factor.hpp, and the configuration
// rates qdot(q, v).
#pragma once

#include <limits>

#include "gimbalsim/dynamics/contact_ends.hpp"
#include "gimbalsim/dynamics/crba.hpp"
#include "gimbalsim/dynamics/kinematics.hpp"
#include "gimbalsim/dynamics/rnea.hpp"

namespace gimbalsim {

/// Joint torques as generalised forces (a pure couple about each joint axis).
template <class V>
void applyJointTorques(Data<V>& d, const State<V>& s, const Input& u) {
  d.tau.setZero();
  applyJointTorque<V, 0>(d, s, u.tau(0));
  applyJointTorque<V, 1>(d, s, u.tau(1));
}

/// Configuration rates: pdot_W = R_WB v_B, quaternion rate 0.5 q (0, omega_B).
template <class V>
void configurationRates(const State<V>& s, Data<V>& d) {
  constexpr int QJ = State<V>::QJ, NB = V::NB, NJ = V::NJ;
  if constexpr (V::kFloating) {
    const Quat quat = Quat(s.q(3), s.q(4), s.q(5), s.q(6)).normalized();
    const Vec3 w = s.v.template head<3>();
    d.qdot.template head<3>() = quat.toRotationMatrix() * s.v.template segment<3>(3);
    const double qw = s.q(3);
    const Vec3 qv = s.q.template segment<3>(4);
    d.qdot(3) = -0.5 * qv.dot(w);
    d.qdot.template segment<3>(4) = 0.5 * (qw * w + qv.cross(w));
  }
  d.qdot.template segment<NJ>(QJ) = s.v.template segment<NJ>(NB);
}

/// Fills d.qdot, d.vdot (and d.contact) at state s under input u.
template <class V>
GIMBALSIM_FLATTEN void forwardDynamics(const Model& m, Data<V>& d, const State<V>& s, const Input& u) {
  ++d.stats.derivatives;
  kinematics(m, d, s.q, s.v);
  detail::rneaBias(m, d, s.v, d.bias);
  crba(m, d);
  applyJointTorques(d, s, u);
  if constexpr (V::kContact) allContacts(m, d, s);
  // M vdot = tau - C, M factored into d.mass (base block in closed form, Schur complement).
  const bool spd = factorMass(d.M, d.mass);
  d.vdot = d.tau - d.bias;
  solveMass(d.mass, d.vdot, d.vdot);
  if (!spd) {
    d.vdot.setConstant(std::numeric_limits<double>::quiet_NaN());
  } else if constexpr (V::kStick) {
    if (m.bearing[1].friction == FrictionLaw::CoulombStick && s.in_contact[0] && s.friction_mode == 0) {
      stickClosure(m, d, s.q, s.v);
    }
  }
  configurationRates(s, d);
}

}  // namespace gimbalsim
