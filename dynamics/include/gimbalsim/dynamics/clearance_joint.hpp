// Kinematics and contact force of the planar clearance joint (docs/MODEL.md
// section 4, paper eq. 1-12). The journal centre relative to the bearing
// centre is (ecc_x, ecc_y) in the joint-plane basis (u1, u2); k = u1 x u2.
// Written for either gimbal joint through its group of chain coordinates
// [ecc_x, ecc_y, theta] (variant.hpp): joint 2's bearing is on shaft 1,
// joint 1's on the base.
#pragma once

#include <cmath>

#include "gimbalsim/dynamics/contact_law.hpp"
#include "gimbalsim/dynamics/data.hpp"

namespace gimbalsim {

/// The one planar clearance joint of a variant with a single contact end
/// (0: azimuth, 1: elevation): the default joint of the functions below.
template <class V>
constexpr int planarJoint() {
  static_assert(V::NC == 1, "a single planar clearance joint");
  return V::kKind1 == ClearanceKind::Planar ? 0 : 1;
}

/// Layout of planar joint J's group: ecc_x, ecc_y at q(QE), q(QE + 1) and
/// v(VE), v(VE + 1), its angle's rate at v(VE + 2); the joint axis (in the
/// bearing body's coordinates) and its contact end.
template <class V, int J>
struct PlanarGroup {
  static_assert(V::kind(J) == ClearanceKind::Planar, "joint J is a planar clearance joint");
  static constexpr int QE = State<V>::QJ + V::group(J);
  static constexpr int VE = V::NB + V::group(J);
  static constexpr int END = V::firstEnd(J);
  static const Vec3& axis(const Model& m) { return J == 0 ? m.k1_B : m.k2_S1; }
};

/// Tangent t of the contact: the normal n turned +90 deg about k2.
inline Vec2 contactTangent(const Vec2& n) { return Vec2(-n.y(), n.x()); }

/// Arm of the tangential force about the journal centre [m]: the pair's
/// forces act at the midpoint of Q_i and Q_j, (R_i + R_j - e) / 2 along n.
inline double contactArm(const ContactParams& cp, double e) {
  return 0.5 * (cp.bearing_radius + cp.journal_radius - e);
}

/// Penetration delta = e - c [m] and its rate d(delta)/dt [m/s] straight from
/// the coordinates (no kinematics needed).
struct Gap {
  double delta;
  double rate;
};

template <class V, int J = planarJoint<V>(), class Q, class W>
Gap clearanceGap(const Model& m, const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<W>& v) {
  using G = PlanarGroup<V, J>;
  const double ex = q(G::QE), ey = q(G::QE + 1);
  const double e = std::hypot(ex, ey);
  const double rate = e > 0.0 ? (ex * v(G::VE) + ey * v(G::VE + 1)) / e : 0.0;
  return {e - m.bearing[J].clearance, rate};
}

/// Component along the joint axis k of the bearing body's angular velocity
/// [rad/s] (linear in v): shaft 1 for joint 2, the base for joint 1.
template <class V, int J, class Q, class W>
double parentRateAlongAxis(const Model& m, const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<W>& v) {
  if constexpr (J == 0) {
    if constexpr (V::kFloating) return v.template head<3>().dot(m.k1_B);
    return 0.0;
  } else {
    // theta1 is the last coordinate of joint 1's group.
    constexpr int QT1 = State<V>::QJ + V::N1 - 1, VT1 = V::NB + V::N1 - 1;
    const Vec3& k1 = m.chain[V::N1 - 1].axis;
    double w = v(VT1) * k1.dot(m.k2_S1);
    if constexpr (V::kFloating) {
      // R_PC^T omega_B with R_PC the rotation about k1 by theta1.
      const Vec3 wB = v.template head<3>();
      const double c = std::cos(q(QT1)), s = std::sin(q(QT1));
      const Vec3 wS1 = c * wB - s * k1.cross(wB) + (1.0 - c) * k1.dot(wB) * k1;
      w += wS1.dot(m.k2_S1);
    }
    return w;
  }
}

/// Tangential relative velocity of the material points v_t(q, v) [m/s] (the
/// same quantity clearanceContact() writes to ContactEval::vt), linear in v.
template <class V, int J = planarJoint<V>(), class Q, class W>
double tangentialVelocity(const Model& m, const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<W>& v) {
  using G = PlanarGroup<V, J>;
  const ContactParams& cp = m.bearing[J];
  const double ex = q(G::QE), ey = q(G::QE + 1);
  const double e = std::hypot(ex, ey);
  if (!(e > 0.0)) return 0.0;
  const Vec2 t(-ey / e, ex / e);
  return t.x() * v(G::VE) + t.y() * v(G::VE + 1) + v(G::VE + 2) * cp.journal_radius +
         (e - cp.clearance) * parentRateAlongAxis<V, J>(m, q, v);
}

/// The part of dv_t/dt that does not go through vdot: (d v_t / d q) qdot at
/// fixed v [m/s^2]. With it, dv_t/dt = tangentialVelocity(q, vdot) + this.
template <class V, int J = planarJoint<V>(), class Q, class W>
double tangentialVelocityRateAtFixedV(const Model& m, const Eigen::MatrixBase<Q>& q,
                                      const Eigen::MatrixBase<W>& v) {
  using G = PlanarGroup<V, J>;
  const double c_J = m.bearing[J].clearance;
  const double ex = q(G::QE), ey = q(G::QE + 1);
  const double e = std::hypot(ex, ey);
  if (!(e > 0.0)) return 0.0;
  const Vec2 n(ex / e, ey / e), t = contactTangent(n);
  const Vec2 de(v(G::VE), v(G::VE + 1));
  // dt/dt = -(de . t / e) n;  d(e - c)/dt = de . n.
  double r = -de.dot(t) * de.dot(n) / e + de.dot(n) * parentRateAlongAxis<V, J>(m, q, v);
  if constexpr (V::kFloating && J == 1) {
    // shaft 1's rate along k2 turns with theta1 (the base's along k1 does not)
    constexpr int QT1 = State<V>::QJ + V::N1 - 1, VT1 = V::NB + V::N1 - 1;
    const Vec3& k1 = m.chain[V::N1 - 1].axis;
    const Vec3 wB = v.template head<3>();
    const double c = std::cos(q(QT1)), s = std::sin(q(QT1));
    const Vec3 dwS1 = -s * wB - c * k1.cross(wB) + s * k1.dot(wB) * k1;  // d/dtheta1 of R^T wB
    r += (e - c_J) * v(VT1) * dwS1.dot(m.k2_S1);
  }
  return r;
}

/// The bearing body's angular velocity in its own coordinates [rad/s]:
/// shaft 1 for joint 2, the base for joint 1. Needs kinematics().
template <class V, int J>
Vec3 bearingBodyRate(const Data<V>& d) {
  if constexpr (J == 1) return d.v[V::G2 - 1].template head<3>();
  return V::kFloating ? Vec3(d.v_base.template head<3>()) : Vec3::Zero();
}

/// Contact quantities and forces of planar joint J into its end's
/// d.contact; needs kinematics() for the bearing body's twist.
/// v0 is the impact velocity of the current contact [m/s]; friction_mode the
/// slip direction (+1 / -1) or 0 for stick, read by friction.law
/// coulomb_stick only (in stick F_t is set later by stickClosure()).
template <class V, int J = planarJoint<V>(), class Q, class W>
void clearanceContact(const Model& m, Data<V>& d, const Eigen::MatrixBase<Q>& q,
                      const Eigen::MatrixBase<W>& v, double v0, int friction_mode = 0) {
  using G = PlanarGroup<V, J>;
  const ContactParams& cp = m.bearing[J];
  ContactEval& c = d.contact[G::END];
  const double ex = q(G::QE), ey = q(G::QE + 1);
  c.e = std::hypot(ex, ey);
  c.delta = c.e - cp.clearance;
  if (!(c.e > 0.0)) {
    c.n.setZero();
    c.vn = c.vt = c.fn = c.ft = 0.0;
    return;
  }
  c.n = Vec2(ex / c.e, ey / c.e);
  const Vec2 t = contactTangent(c.n);
  const Vec2 de(v(G::VE), v(G::VE + 1));
  c.vn = de.dot(c.n);
  // Relative velocity of the material points Q_j and Q_i (docs/MODEL.md section 4.3):
  // V = de + dtheta k x (R_j n) + omega_P x (delta n), P the bearing body, so along t:
  const double omegaP_k = bearingBodyRate<V, J>(d).dot(G::axis(m));
  c.vt = de.dot(t) + v(G::VE + 2) * cp.journal_radius + c.delta * omegaP_k;
  c.fn = normalForce(cp, c.delta, c.vn, v0);
  c.ft_required = 0.0;
  if constexpr (V::kFriction) {
    if (V::kStick && cp.friction == FrictionLaw::CoulombStick) {
      c.ft = -static_cast<double>(friction_mode) * cp.mu * c.fn;
    } else {
      c.ft = frictionForce(cp, c.fn, c.vt);
    }
  } else {
    c.ft = 0.0;
  }
}

/// Generalised force of the contact pair: F = -F_n n + F_t t on the journal,
/// -F on the bearing, both at the midpoint of Q_i and Q_j (docs/MODEL.md 4.4), so
/// only the clearance joint's own coordinates see it and momentum is exactly conserved.
template <class V, int J = planarJoint<V>()>
void addContactForces(const Model& m, Data<V>& d) {
  using G = PlanarGroup<V, J>;
  const ContactEval& c = d.contact[G::END];
  if (c.fn == 0.0 && c.ft == 0.0) return;
  const Vec2 F = -c.fn * c.n + c.ft * contactTangent(c.n);
  const double arm = contactArm(m.bearing[J], c.e);
  d.tau(G::VE) += F.x();
  d.tau(G::VE + 1) += F.y();
  d.tau(G::VE + 2) += arm * c.ft;
}

/// Stick closure of coulomb_stick (Filippov): dv_t/dt = a0 + b F_t is affine in
/// F_t (the pair's generalised force is linear in F_t), so in stick F_t =
/// -a0 / b, clamped to |F_t| <= mu F_n. Needs d.mass (factor of M) and d.vdot
/// computed with F_t = 0; adds the pair's tangential force to d.vdot and d.tau
/// and writes ContactEval::ft and ft_required. The one planar contact of a
/// stick-capable variant (V::kStick).
template <class V, class Q, class W>
void stickClosure(const Model& m, Data<V>& d, const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<W>& v) {
  using G = PlanarGroup<V, planarJoint<V>()>;
  ContactEval& c = d.contact[0];
  if (!(c.fn > 0.0)) {
    c.ft = c.ft_required = 0.0;
    return;
  }
  const Vec2 t = contactTangent(c.n);
  const double arm = contactArm(m.bearing[1], c.e);
  typename Data<V>::VecV Qt = Data<V>::VecV::Zero(), w;
  Qt(G::VE) = t.x();
  Qt(G::VE + 1) = t.y();
  Qt(G::VE + 2) = arm;
  solveMass(d.mass, Qt, w);  // vdot per unit F_t
  const double a0 = tangentialVelocity<V>(m, q, d.vdot) + tangentialVelocityRateAtFixedV<V>(m, q, v);
  const double b = tangentialVelocity<V>(m, q, w);
  c.ft_required = b != 0.0 ? -a0 / b : 0.0;
  const double lim = m.bearing[1].mu * c.fn;
  c.ft = std::fmax(-lim, std::fmin(lim, c.ft_required));
  d.vdot += c.ft * w;
  d.tau += c.ft * Qt;
}

/// coulomb_stick: the friction mode consistent at a state on v_t = 0 (or on
/// entering a contact): the slip direction sigma whose friction -sigma mu F_n
/// drives v_t away from 0 in direction sigma, or 0 (stick) when neither does
/// (|F_t required| <= mu F_n; b = d(dv_t/dt)/dF_t > 0 as J_t M^-1 J_t^T).
/// Needs forwardDynamics() just run at the state in stick mode (mode 0).
template <class V>
int consistentFrictionMode(const Model& m, const Data<V>& d) {
  const ContactEval& c = d.contact[0];
  if (!(c.fn > 0.0)) return 0;
  const double lim = m.bearing[1].mu * c.fn;
  const double fr = c.ft_required;
  if (std::fabs(fr) <= lim) return 0;
  return fr > 0.0 ? -1 : 1;
}

}  // namespace gimbalsim
