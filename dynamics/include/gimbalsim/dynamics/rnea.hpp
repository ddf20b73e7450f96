// Recursive Newton-Euler inverse dynamics (RBDA table 5.1): the generalised
// forces tau that produce acceleration vdot at (q, v), with no external force.
// Needs kinematics(q, v) first. With vdot = 0 it gives the bias C(q, v).
#pragma once

#include "gimbalsim/dynamics/data.hpp"

namespace gimbalsim {

template <class V, class W, class A, class T>
void rnea(const Model& m, Data<V>& d, const Eigen::MatrixBase<W>& v,
          const Eigen::MatrixBase<A>& vdot, Eigen::MatrixBase<T>& tau) {
  constexpr int NB = V::NB, NJ = V::NJ;
  if constexpr (V::kFloating) {
    d.a_base = vdot.template head<6>();
    d.f_base = m.I_base * d.a_base + crossForce(d.v_base, m.I_base * d.v_base);
  }
  for (int i = 0; i < NJ; ++i) {
    Vec6 a_parent = Vec6::Zero();
    if (i > 0) {
      a_parent = d.a[i - 1];
    } else if constexpr (V::kFloating) {
      a_parent = d.a_base;
    }
    // a_i = X a_parent + S qdd + v_i x S qd (S constant in body coordinates).
    d.a[i] = d.X[i].motionToChild(a_parent) + d.S[i] * vdot(NB + i) +
             crossMotion(d.v[i], d.S[i] * v(NB + i));
    const Vec6 h = m.I_chain[i] * d.v[i];
    d.f[i] = m.I_chain[i] * d.a[i] + crossForce(d.v[i], h);
  }
  for (int i = NJ - 1; i >= 0; --i) {
    tau(NB + i) = d.S[i].dot(d.f[i]);
    if (i > 0) {
      d.f[i - 1] += d.X[i].forceToParent(d.f[i]);
    } else if constexpr (V::kFloating) {
      d.f_base += d.X[0].forceToParent(d.f[0]);
    }
  }
  if constexpr (V::kFloating) tau.template head<6>() = d.f_base;
}

}  // namespace gimbalsim
