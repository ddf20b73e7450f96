// Forward kinematics of the chain: joint transforms, motion subspaces, body
// twists (RBDA section 4.3, first pass of the recursive Newton-Euler method).
#pragma once

#include "gimbalsim/dynamics/data.hpp"

namespace gimbalsim {

template <class V, class Q, class W>
void kinematics(const Model& m, Data<V>& d, const Eigen::MatrixBase<Q>& q,
                const Eigen::MatrixBase<W>& v) {
  constexpr int QJ = State<V>::QJ, NB = V::NB;
  if constexpr (V::kFloating) d.v_base = v.template head<6>();
  for (int i = 0; i < V::NJ; ++i) {
    const Model::ChainJoint& J = m.chain[i];
    Transform& X = d.X[i];
    const double qi = q(QJ + i);
    if (J.kind == JointKind::Revolute) {
      X.R_PC = axisAngle(J.axis, qi);
      X.r_PC_P = J.origin;
      d.S[i] << J.axis, Vec3::Zero();
    } else {
      X.R_PC.setIdentity();
      X.r_PC_P = J.origin + qi * J.axis;
      d.S[i] << Vec3::Zero(), J.axis;
    }
    if (i == 0) {
      if constexpr (V::kFloating) {
        d.v[0] = X.motionToChild(d.v_base);
      } else {
        d.v[0].setZero();
      }
    } else {
      d.v[i] = X.motionToChild(d.v[i - 1]);
    }
    d.v[i] += d.S[i] * v(NB + i);
  }
}

}  // namespace gimbalsim
