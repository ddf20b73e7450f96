// Recursive Newton-Euler inverse dynamics (RBDA table 5.1): the generalised
// forces tau that produce acceleration vdot at (q, v), with no external force.
// Needs kinematics(q, v) first. With vdot = 0 it gives the bias C(q, v).
//
// Unrolled per Variant like kinematics(): the revolute/prismatic motion
// subspaces S = [k; 0] / [0; k] are used through their non-zero half, and the
// clearance joint's massless virtual bodies carry no inertial force (theirs is
// exactly zero), so they only pass their child's force on. Bit-identical to
// the generic 6-D recursion.
#pragma once

#include "gimbalsim/dynamics/kinematics.hpp"

namespace gimbalsim {

namespace detail {

/// a_i = X a_parent + S qdd + v_i x (S qd) for chain joint i (S constant in
/// body coordinates). Written so that each coefficient sees the same
/// operations as the 6-D expression (the terms of S's zero half are exact 0s).
/// ParentZero / QddZero: a_parent or qdd is known to be zero (bias forces).
template <class V, int i, bool ParentZero, bool QddZero>
GIMBALSIM_INLINE void jointAcceleration(const Transform& X, const Vec3& axis, const Vec6& a_parent,
                                        const Vec6& v_i, double qd, double qdd, Vec6& a_i) {
  const Vec3 kqd = axis * qd;
  if constexpr (ParentZero && QddZero) {
    // X 0 + S 0 + v x S qd
    if constexpr (chainJointKind<V>(i) == JointKind::Revolute) {
      a_i.template head<3>() = v_i.template head<3>().cross(kqd);
      a_i.template tail<3>() = v_i.template tail<3>().cross(kqd);
    } else {
      a_i.template head<3>().setZero();
      a_i.template tail<3>() = v_i.template head<3>().cross(kqd);
    }
    return;
  }
  Vec6 Xa;
  if constexpr (ParentZero) {
    Xa.setZero();
  } else {
    Xa = jointMotionToChild<V, i>(X, a_parent);
  }
  Vec3 Xa_S = chainJointKind<V>(i) == JointKind::Revolute ? Xa.template head<3>() : Xa.template tail<3>();
  if constexpr (!QddZero) Xa_S += axis * qdd;
  if constexpr (chainJointKind<V>(i) == JointKind::Revolute) {
    // S qd = [k qd; 0]: v x S qd = [w x k qd; v_o x k qd].
    a_i.template head<3>() = Xa_S + v_i.template head<3>().cross(kqd);
    a_i.template tail<3>() = Xa.template tail<3>() + v_i.template tail<3>().cross(kqd);
  } else {
    // S qd = [0; k qd]: v x S qd = [0; w x k qd].
    a_i.template head<3>() = Xa.template head<3>();
    a_i.template tail<3>() = Xa_S + v_i.template head<3>().cross(kqd);
  }
}

/// The RNEA of rnea() below; VdotZero: vdot = 0 (bias forces C(q, v) v).
template <bool VdotZero, class V, class W, class A, class T>
GIMBALSIM_INLINE void rneaImpl(const Model& m, Data<V>& d, const Eigen::MatrixBase<W>& v,
                               const Eigen::MatrixBase<A>& vdot, Eigen::MatrixBase<T>& tau) {
  constexpr int NB = V::NB, NJ = V::NJ;
  if constexpr (V::kFloating) {
    if constexpr (VdotZero) {
      d.a_base.setZero();
      d.f_base = crossForce(d.v_base, m.I_base * d.v_base);  // I 0 + v x* I v
    } else {
      d.a_base = vdot.template head<6>();
      d.f_base = m.I_base * d.a_base + crossForce(d.v_base, m.I_base * d.v_base);
    }
  }
  staticFor<NJ>([&](auto I) GIMBALSIM_FLATTEN_LAMBDA {
    constexpr int i = I;
    constexpr bool parent_zero = i == 0 && (VdotZero || !V::kFloating);
    const Vec6& a_parent = i > 0 ? d.a[i > 0 ? i - 1 : 0] : d.a_base;
    jointAcceleration<V, i, parent_zero, VdotZero>(d.X[i], m.chain[i].axis, a_parent, d.v[i], v(NB + i),
                                                   VdotZero ? 0.0 : vdot(NB + i), d.a[i]);
    if constexpr (chainBodyMassless<V>(i)) {
      assert(m.I_chain[i].m == 0.0 && m.I_chain[i].h.isZero(0.0));
      d.f[i].setZero();  // I = 0: no inertial force (set below from the child)
    } else {
      const Vec6 h = m.I_chain[i] * d.v[i];
      d.f[i] = m.I_chain[i] * d.a[i] + crossForce(d.v[i], h);
    }
  });
  staticFor<NJ, /*Reverse=*/true>([&](auto I) GIMBALSIM_FLATTEN_LAMBDA {
    constexpr int i = I;
    tau(NB + i) = subspaceDot<V, i>(m.chain[i].axis, d.f[i]);
    if constexpr (i > 0) {
      if constexpr (chainBodyMassless<V>(i - 1)) {
        d.f[i - 1] = jointForceToParent<V, i>(d.X[i], d.f[i]);  // 0 + X^T f
      } else {
        d.f[i - 1] += jointForceToParent<V, i>(d.X[i], d.f[i]);
      }
    } else if constexpr (V::kFloating) {
      d.f_base += jointForceToParent<V, 0>(d.X[0], d.f[0]);
    }
  });
  if constexpr (V::kFloating) tau.template head<6>() = d.f_base;
}

/// Bias forces C(q, v) v = rnea(q, v, 0), without the zero-acceleration terms.
template <class V, class W, class T>
GIMBALSIM_INLINE void rneaBias(const Model& m, Data<V>& d, const Eigen::MatrixBase<W>& v,
                               Eigen::MatrixBase<T>& tau) {
  rneaImpl</*VdotZero=*/true>(m, d, v, v, tau);
}

}  // namespace detail

template <class V, class W, class A, class T>
GIMBALSIM_FLATTEN void rnea(const Model& m, Data<V>& d, const Eigen::MatrixBase<W>& v,
          const Eigen::MatrixBase<A>& vdot, Eigen::MatrixBase<T>& tau) {
  detail::rneaImpl</*VdotZero=*/false>(m, d, v, vdot, tau);
}

}  // namespace gimbalsim
