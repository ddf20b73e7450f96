// Kinematics and contact force of the planar clearance joint (MODEL.md
// section 2, paper eq. 1-12). The journal centre relative to the bearing
// centre is (ecc_x, ecc_y) in the joint-plane basis (u1, u2); k2 = u1 x u2.
#pragma once

#include <cmath>

#include "gimbalsim/dynamics/contact_law.hpp"
#include "gimbalsim/dynamics/data.hpp"

namespace gimbalsim {

/// Penetration delta = e - c [m] and its rate d(delta)/dt [m/s] straight from
/// the coordinates (no kinematics needed).
struct Gap {
  double delta;
  double rate;
};

template <class V, class Q, class W>
Gap clearanceGap(const Model& m, const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<W>& v) {
  static_assert(V::kClearance);
  constexpr int QJ = State<V>::QJ, NB = V::NB;
  const double ex = q(QJ + 1), ey = q(QJ + 2);
  const double e = std::hypot(ex, ey);
  const double rate = e > 0.0 ? (ex * v(NB + 1) + ey * v(NB + 2)) / e : 0.0;
  return {e - m.contact.clearance, rate};
}

/// Contact quantities and forces; needs kinematics() for shaft 1's twist.
/// v0 is the impact velocity of the current contact [m/s].
template <class V, class Q, class W>
void clearanceContact(const Model& m, Data<V>& d, const Eigen::MatrixBase<Q>& q,
                      const Eigen::MatrixBase<W>& v, double v0) {
  static_assert(V::kClearance);
  constexpr int QJ = State<V>::QJ, NB = V::NB;
  const ContactParams& cp = m.contact;
  ContactEval& c = d.contact;
  const double ex = q(QJ + 1), ey = q(QJ + 2);
  c.e = std::hypot(ex, ey);
  c.delta = c.e - cp.clearance;
  if (!(c.e > 0.0)) {
    c.n.setZero();
    c.vn = c.vt = c.fn = c.ft = 0.0;
    return;
  }
  c.n = Vec2(ex / c.e, ey / c.e);
  const Vec2 t(-c.n.y(), c.n.x());  // n turned +90 deg about k2
  const Vec2 de(v(NB + 1), v(NB + 2));
  c.vn = de.dot(c.n);
  // Relative velocity of the material points Q_j and Q_i (MODEL.md 2):
  // V = de + dtheta2 k2 x (R_j n) + omega_1 x (delta n), so along t:
  const double omega1_k2 = d.v[0].template head<3>().dot(m.k2_S1);
  c.vt = de.dot(t) + v(NB + 3) * cp.journal_radius + c.delta * omega1_k2;
  c.fn = normalForce(cp, c.delta, c.vn, v0);
  if constexpr (V::kFriction) {
    c.ft = frictionForce(cp, c.fn, c.vt);
  } else {
    c.ft = 0.0;
  }
}

/// Generalised force of the contact pair: F = -F_n n + F_t t on the journal,
/// -F on the bearing, both at the midpoint of Q_i and Q_j (MODEL.md 2), so
/// only the joint-2 coordinates see it and momentum is exactly conserved.
template <class V>
void addContactForces(const Model& m, Data<V>& d) {
  constexpr int NB = V::NB;
  const ContactEval& c = d.contact;
  if (c.fn == 0.0 && c.ft == 0.0) return;
  const Vec2 t(-c.n.y(), c.n.x());
  const Vec2 F = -c.fn * c.n + c.ft * t;
  // Midpoint lies (R_i + R_j - e)/2 along n from the journal centre.
  const double arm = 0.5 * (m.contact.bearing_radius + m.contact.journal_radius - c.e);
  d.tau(NB + 1) += F.x();
  d.tau(NB + 2) += F.y();
  d.tau(NB + 3) += arm * c.ft;
}

}  // namespace gimbalsim
