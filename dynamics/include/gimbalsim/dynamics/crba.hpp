// Composite-rigid-body algorithm for the joint-space inertia matrix M(q)
// (RBDA table 6.2), floating base as a 6-dof joint with S = identity.
// Needs kinematics(q, .) first.
//
// Unrolled per Variant like kinematics(): prismatic joints shift an inertia
// without rotating it, the massless virtual bodies of the clearance joint add
// nothing to a composite, and S = [k; 0] / [0; k] is used through its
// non-zero half. Bit-identical to the generic 6-D recursion.
#pragma once

#include <array>

#include "gimbalsim/dynamics/kinematics.hpp"

namespace gimbalsim {

namespace detail {

/// Ic.toParent(X) of chain joint i: the composite inertia of body i about its
/// parent's origin in parent coordinates (a prismatic joint only shifts it).
template <class V, int i>
GIMBALSIM_INLINE SpatialInertia inertiaToParent(const SpatialInertia& I, const Transform& X) {
  if constexpr (chainJointKind<V>(i) == JointKind::Prismatic) {
    SpatialInertia p;  // R = identity: R h = h, R Ibar R^T = Ibar
    const Vec3& r = X.r_PC_P;
    p.m = I.m;
    p.h = I.h + I.m * r;
    p.Ibar = I.Ibar - SpatialInertia::shiftTerm(I.m * r, r, I.h);
    return p;
  } else {
    return I.toParent(X);
  }
}

/// Ic S of chain joint i: [Ibar k; -h x k] (revolute) or [h x k; m k] (prismatic).
template <class V, int i>
GIMBALSIM_INLINE Vec6 inertiaTimesSubspace(const SpatialInertia& I, const Vec3& k) {
  Vec6 F;
  if constexpr (chainJointKind<V>(i) == JointKind::Revolute) {
    double hk[3];
    kernel::mul3(I.Ibar, k.x(), k.y(), k.z(), F.data());
    kernel::cross3(I.h.data(), k.data(), hk);
    F(3) = -hk[0], F(4) = -hk[1], F(5) = -hk[2];
  } else {
    kernel::cross3(I.h.data(), k.data(), F.data());
    F.template tail<3>() = I.m * k;
  }
  return F;
}

}  // namespace detail

template <class V>
GIMBALSIM_FLATTEN void crba(const Model& m, Data<V>& d) {
  constexpr int NB = V::NB, NJ = V::NJ;
  // Work on local copies: the stores into M below then cannot alias them.
  const std::array<Transform, NJ> X = d.X;
  std::array<SpatialInertia, NJ> Ic;
  Ic[NJ - 1] = m.I_chain[NJ - 1];
  SpatialInertia Ic_base;
  staticFor<NJ, /*Reverse=*/true>([&](auto I) {
    constexpr int i = I;
    if constexpr (i > 0 || V::kFloating) {
      const SpatialInertia Ip = detail::inertiaToParent<V, i>(Ic[i], X[i]);
      if constexpr (i > 0) {
        if constexpr (chainBodyMassless<V>(i - 1)) {
          assert(m.I_chain[i - 1].m == 0.0 && m.I_chain[i - 1].Ibar.isZero(0.0));
          Ic[i - 1] = Ip;  // 0 + Ip
        } else {
          Ic[i - 1] = m.I_chain[i - 1];
          Ic[i - 1] += Ip;
        }
      } else {
        Ic_base = m.I_base;
        Ic_base += Ip;
      }
    }
  });
  // Column i: F = Ic_i S_i carried down the chain, M(j, i) = S_j . F.
  double Mjj[NJ][NJ];
  std::array<Vec6, NJ> Fb;  // floating base: the base rows of column i
  staticFor<NJ>([&](auto I) {
    constexpr int i = I;
    const Vec3 k_i = m.chain[i].axis;
    Vec6 F = detail::inertiaTimesSubspace<V, i>(Ic[i], k_i);
    Mjj[i][i] = detail::subspaceDot<V, i>(k_i, F);
    staticFor<i, /*Reverse=*/true>([&](auto J) {  // j = i .. 1
      constexpr int j = J + 1;
      F = detail::jointForceToParent<V, j>(X[j], F);
      Mjj[j - 1][i] = detail::subspaceDot<V, j - 1>(m.chain[j - 1].axis, F);
    });
    if constexpr (V::kFloating) Fb[i] = detail::jointForceToParent<V, 0>(X[0], F);
  });
  for (int i = 0; i < NJ; ++i) {
    for (int j = 0; j <= i; ++j) d.M(NB + j, NB + i) = d.M(NB + i, NB + j) = Mjj[j][i];
  }
  if constexpr (V::kFloating) {
    for (int i = 0; i < NJ; ++i) {
      d.M.template block<6, 1>(0, NB + i) = Fb[i];
      d.M.template block<1, 6>(NB + i, 0) = Fb[i].transpose();
    }
    d.M.template topLeftCorner<6, 6>() = Ic_base.matrix();
    d.Ic_base = Ic_base;
  }
  d.Ic = Ic;
}

}  // namespace gimbalsim
