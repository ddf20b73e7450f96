// The contact ends of a variant, whatever its joint kinds: a planar
// clearance joint has one end (clearance_joint.hpp), a spatial one two, at
// its bearing's end planes (spatial_joint.hpp). Here the joints' groups are
// mapped to those contacts, so the integrator sees NC ends with a gap each
// and forwardDynamics() one call for every contact force.
#pragma once

#include "gimbalsim/dynamics/clearance_joint.hpp"
#include "gimbalsim/dynamics/spatial_joint.hpp"

namespace gimbalsim {

/// Layout of spatial joint J's group [p_x, p_y, alpha, beta, theta] in q, v,
/// its first contact end, and the bearing frame B (u1, u2, k) in the bearing
/// body's coordinates.
template <class V, int J>
struct SpatialGroup {
  static_assert(V::kind(J) == ClearanceKind::Spatial, "joint J is a spatial clearance joint");
  static constexpr int QG = State<V>::QJ + V::group(J);
  static constexpr int VG = V::NB + V::group(J);
  static constexpr int END = V::firstEnd(J);
  static Vec3 toB(const Model& m, const Vec3& w_parent) {
    return J == 0 ? Vec3(w_parent.dot(m.u1_B), w_parent.dot(m.u2_B), w_parent.dot(m.k1_B))
                  : Vec3(w_parent.dot(m.u1_S1), w_parent.dot(m.u2_S1), w_parent.dot(m.k2_S1));
  }
};

/// Gap of end `side` (0: s = -1, 1: s = +1 for a spatial joint; 0 for a
/// planar one) of clearance joint J: delta [m] and its time derivative [m/s].
template <class V, int J, class Q, class W>
Gap jointEndGap(const Model& m, int side, const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<W>& v) {
  if constexpr (V::kind(J) == ClearanceKind::Planar) {
    (void)side;
    return clearanceGap<V, J>(m, q, v);
  } else if constexpr (V::kind(J) == ClearanceKind::Spatial) {
    using G = SpatialGroup<V, J>;
    const ContactParams& cp = m.bearing[J];
    Gap g{};
    spatialEndGap(cp.clearance, cp.bearing_length, side == 0 ? -1.0 : 1.0, q.template segment<5>(G::QG),
                  v.template segment<5>(G::VG), g.delta, g.rate);
    return g;
  } else {
    (void)m, (void)side, (void)q, (void)v;
    return {-1.0, 0.0};  // an ideal joint has no end
  }
}

/// Gap of contact end e (0 <= e < V::NC).
template <class V, class Q, class W>
Gap endGap(const Model& m, int e, const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<W>& v) {
  if (e < V::firstEnd(1)) return jointEndGap<V, 0>(m, e, q, v);
  return jointEndGap<V, 1>(m, e - V::firstEnd(1), q, v);
}

/// Contact of clearance joint J at state s into d.contact (its ends), d.tau
/// and d.tilt; needs kinematics().
template <class V, int J>
void jointContact(const Model& m, Data<V>& d, const State<V>& s) {
  if constexpr (V::kind(J) == ClearanceKind::Planar) {
    constexpr int E = PlanarGroup<V, J>::END;
    clearanceContact<V, J>(m, d, s.q, s.v, s.in_contact[E] ? s.v0[E] : kOnsetNotLocated,
                           s.in_contact[E] ? s.friction_mode : 0);
    addContactForces<V, J>(m, d);
  } else if constexpr (V::kind(J) == ClearanceKind::Spatial) {
    using G = SpatialGroup<V, J>;
    SpatialContact& out = d.spatial[J];
    const ContactParams& cp = m.bearing[J];
    spatialContact(cp, cp.bearing_length, s.q.template segment<5>(G::QG), s.v.template segment<5>(G::VG),
                   G::toB(m, bearingBodyRate<V, J>(d)),
                   {s.in_contact[G::END] ? s.v0[G::END] : kOnsetNotLocated,
                    s.in_contact[G::END + 1] ? s.v0[G::END + 1] : kOnsetNotLocated},
                   out);
    for (int i = 0; i < 2; ++i) {
      const SpatialEnd& se = out.end[i];
      ContactEval& c = d.contact[G::END + i];
      c.e = se.e;
      c.n = se.n_B.template head<2>();
      c.delta = se.delta;
      c.vn = se.vn;
      c.vt = se.vt_B.norm();
      c.fn = se.fn;
      c.ft = se.ft_B.norm();
      c.ft_required = 0.0;
    }
    d.tau.template segment<5>(G::VG) += out.tau;
  }
}

/// Generalised direction of end e's normal force (the force of a unit
/// normal on the joint's coordinates) into nv; false when the end has no
/// normal (journal centred). Needs forwardDynamics() at s.
template <class V>
bool endNormalDirection(const Model& m, const Data<V>& d, const State<V>& s, int e,
                        typename Data<V>::VecV& nv) {
  (void)m;
  const int j = V::endJoint(e);
  if (V::kind(j) == ClearanceKind::Planar) {
    const int qe = State<V>::QJ + V::group(j), ve = V::NB + V::group(j);
    const double ex = s.q(qe), ey = s.q(qe + 1), r = std::hypot(ex, ey);
    if (!(r > 0.0)) return false;
    nv(ve) = ex / r;
    nv(ve + 1) = ey / r;
    return true;
  }
  if constexpr (Data<V>::kSpatial) {
    const SpatialEnd& se = d.spatial[j].end[e - V::firstEnd(j)];
    if (!(se.e > 0.0)) return false;
    const int qg = State<V>::QJ + V::group(j), vg = V::NB + V::group(j);
    const std::array<Vec3, 3> a = spatialHingeAxes(s.q(qg + 2), s.q(qg + 3));
    const Vec3 r = se.M_B - Vec3(s.q(qg), s.q(qg + 1), 0.0);
    nv(vg) = se.n_B.x();
    nv(vg + 1) = se.n_B.y();
    for (int h = 0; h < 3; ++h) nv(vg + 2 + h) = a[h].dot(r.cross(se.n_B));
    return true;
  }
  return false;
}

/// Energy stored in the Hertz springs of every contact end at (q, v) [J]:
/// K_e delta^(n+1) / (n+1) per penetrating end, K_e = K (planar) or K / 2
/// (each end of a spatial joint).
template <class V, class Q, class W>
double hertzEnergy(const Model& m, const Eigen::MatrixBase<Q>& q, const Eigen::MatrixBase<W>& v) {
  double U = 0.0;
  for (int e = 0; e < V::NC; ++e) {
    const int j = V::endJoint(e);
    const ContactParams& c = m.bearing[j];
    const double delta = endGap<V>(m, e, q, v).delta;
    const double K = V::kind(j) == ClearanceKind::Spatial ? 0.5 * c.K : c.K;
    if (delta > 0.0) U += K * std::pow(delta, c.exponent + 1.0) / (c.exponent + 1.0);
  }
  return U;
}

/// Every clearance joint's contact (joint 1's first).
template <class V>
void allContacts(const Model& m, Data<V>& d, const State<V>& s) {
  jointContact<V, 0>(m, d, s);
  jointContact<V, 1>(m, d, s);
}

/// Motor torque tau_j of joint j: a couple about the joint axis, on theta_j
/// alone unless the joint is spatial (then the tilt hinges see it too).
template <class V, int J>
void applyJointTorque(Data<V>& d, const State<V>& s, double tau) {
  if constexpr (V::kind(J) == ClearanceKind::Spatial) {
    constexpr int QG = State<V>::QJ + V::group(J);
    d.tau.template segment<5>(V::NB + V::group(J)) += spatialCoupleForce(tau, s.q(QG + 2), s.q(QG + 3));
  } else {
    (void)s;
    d.tau(V::NB + V::theta(J)) = tau;
  }
}

}  // namespace gimbalsim
