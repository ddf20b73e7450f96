// Composite-rigid-body algorithm for the joint-space inertia matrix M(q)
// (RBDA table 6.2), floating base as a 6-dof joint with S = identity.
// Needs kinematics(q, .) first.
#pragma once

#include "gimbalsim/dynamics/data.hpp"

namespace gimbalsim {

template <class V>
void crba(const Model& m, Data<V>& d) {
  constexpr int NB = V::NB, NJ = V::NJ;
  for (int i = 0; i < NJ; ++i) d.Ic[i] = m.I_chain[i];
  for (int i = NJ - 1; i >= 0; --i) {
    const SpatialInertia Ip = d.Ic[i].toParent(d.X[i]);
    if (i > 0) {
      d.Ic[i - 1] += Ip;
    } else if constexpr (V::kFloating) {
      d.Ic_base = m.I_base;
      d.Ic_base += Ip;
    }
  }
  for (int i = 0; i < NJ; ++i) {
    Vec6 F = d.Ic[i] * d.S[i];
    d.M(NB + i, NB + i) = d.S[i].dot(F);
    for (int j = i; j > 0; --j) {
      F = d.X[j].forceToParent(F);
      d.M(NB + j - 1, NB + i) = d.M(NB + i, NB + j - 1) = d.S[j - 1].dot(F);
    }
    if constexpr (V::kFloating) {
      F = d.X[0].forceToParent(F);
      d.M.template block<6, 1>(0, NB + i) = F;
      d.M.template block<1, 6>(NB + i, 0) = F.transpose();
    }
  }
  if constexpr (V::kFloating) d.M.template topLeftCorner<6, 6>() = d.Ic_base.matrix();
}

}  // namespace gimbalsim
