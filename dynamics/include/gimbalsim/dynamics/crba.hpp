// Composite-rigid-body algorithm for the joint-space inertia matrix M(q)
// (RBDA table 6.2), floating base as a 6-dof joint with S = identity.
// Needs kinematics(q, .) first.
//
// Unrolled per Variant like kinematics(): prismatic joints shift an inertia
// without rotating it, the massless virtual bodies of the clearance joint add
// nothing to a composite, and S = [k; 0] / [0; k] is used through its
// non-zero half. Bit-identical to the generic 6-D recursion.
#pragma once

#include "gimbalsim/dynamics/kinematics.hpp"

namespace gimbalsim {

namespace detail {

/// A SpatialInertia as plain scalars (I = Ibar, column-major like Mat3's
/// storage): the CRBA's composite inertias, and the CRBA's only implementation of
/// composing and shifting them. Everything the CRBA reads was written by
/// scalar stores (mixing scalar stores with Eigen's 16-byte packet loads of
/// the same data stalls store forwarding).
struct InertiaS {
  double m;
  double h[3];
  double I[9];
};

GIMBALSIM_INLINE void load(const SpatialInertia& a, InertiaS& b) {
  b.m = a.m;
  for (int k = 0; k < 3; ++k) b.h[k] = a.h(k);
  for (int k = 0; k < 9; ++k) b.I[k] = a.Ibar(k);
}

/// p = a + b, entry by entry.
GIMBALSIM_INLINE void add(const SpatialInertia& a, const InertiaS& b, InertiaS& p) {
  p.m = a.m + b.m;
  for (int k = 0; k < 3; ++k) p.h[k] = a.h(k) + b.h[k];
  for (int k = 0; k < 9; ++k) p.I[k] = a.Ibar(k) + b.I[k];
}

/// S = m [r]x[r]x + [r]x[Rh]x + [Rh]x[r]x given mr = m r (the shift of
/// inertiaToParent). Every entry of a product of two skew matrices has at
/// most two non-zero terms, so writing them out equals the 3x3 products bit
/// for bit.
GIMBALSIM_INLINE void shiftTerm(const double* mr, const double* r, const double* Rh, double* S) {
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      if (i == j) {
        const int a = i == 0 ? 1 : 0, b = i == 2 ? 1 : 2;  // the two other indices, ascending
        const double A = -(mr[a] * r[a]) - mr[b] * r[b];
        const double B = -(r[a] * Rh[a]) - r[b] * Rh[b];
        const double C = -(Rh[a] * r[a]) - Rh[b] * r[b];
        S[i + 3 * j] = (A + B) + C;
      } else {
        S[i + 3 * j] = (r[i] * mr[j] + Rh[i] * r[j]) + r[i] * Rh[j];
      }
    }
  }
}

/// The inertia a of chain body i about the parent origin in parent
/// coordinates (X^T I X for the motion transform X = ^C X_P): m, R h + m r,
/// R Ibar R^T - (m [r]x[r]x + [r]x[Rh]x + [Rh]x[r]x), each product in Eigen's
/// order (kernel::mul3). A prismatic joint has R = identity, so it only
/// shifts the inertia.
template <class V, int i>
GIMBALSIM_INLINE void inertiaToParent(const InertiaS& a, const Transform& X, InertiaS& p) {
  const double* r = X.r_PC_P.data();
  double Rh[3], S[9], mr[3];
  p.m = a.m;
  for (int k = 0; k < 3; ++k) mr[k] = a.m * r[k];
  if constexpr (chainJointKind<V>(i) == JointKind::Prismatic) {
    for (int k = 0; k < 3; ++k) Rh[k] = a.h[k];
    for (int k = 0; k < 9; ++k) p.I[k] = a.I[k];
  } else {
    const double* R = X.R_PC.data();
    double T[9];  // R Ibar, then (R Ibar) R^T
    kernel::mul3(R, a.h[0], a.h[1], a.h[2], Rh);
    for (int j = 0; j < 3; ++j) kernel::mul3(R, a.I[3 * j], a.I[3 * j + 1], a.I[3 * j + 2], T + 3 * j);
    for (int j = 0; j < 3; ++j) kernel::mul3(T, R[j], R[j + 3], R[j + 6], p.I + 3 * j);
  }
  for (int k = 0; k < 3; ++k) p.h[k] = Rh[k] + mr[k];
  shiftTerm(mr, r, Rh, S);
  for (int k = 0; k < 9; ++k) p.I[k] -= S[k];
}

/// Ic S of chain joint i: [Ibar k; -h x k] (revolute) or [h x k; m k] (prismatic).
template <class V, int i>
GIMBALSIM_INLINE void inertiaTimesSubspace(const InertiaS& a, const Vec3& k, double* F) {
  if constexpr (chainJointKind<V>(i) == JointKind::Revolute) {
    double hk[3];
    kernel::mul3(a.I, k.x(), k.y(), k.z(), F);
    kernel::cross3(a.h, k.data(), hk);
    F[3] = -hk[0], F[4] = -hk[1], F[5] = -hk[2];
  } else {
    kernel::cross3(a.h, k.data(), F);
    F[3] = a.m * k.x(), F[4] = a.m * k.y(), F[5] = a.m * k.z();
  }
}

}  // namespace detail

template <class V>
GIMBALSIM_FLATTEN void crba(const Model& m, Data<V>& d) {
  constexpr int NB = V::NB, NJ = V::NJ;
  detail::InertiaS Ic[NJ], Ic_base;
  detail::load(m.I_chain[NJ - 1], Ic[NJ - 1]);
  staticFor<NJ, /*Reverse=*/true>([&](auto I) GIMBALSIM_FLATTEN_LAMBDA {
    constexpr int i = I;
    if constexpr (i > 0 || V::kFloating) {
      detail::InertiaS Ip;
      detail::inertiaToParent<V, i>(Ic[i], d.X[i], Ip);
      if constexpr (i > 0) {
        if constexpr (chainBodyMassless<V>(i - 1)) {
          assert(m.I_chain[i - 1].m == 0.0 && m.I_chain[i - 1].Ibar.isZero(0.0));
          Ic[i - 1] = Ip;  // 0 + Ip
        } else {
          detail::add(m.I_chain[i - 1], Ip, Ic[i - 1]);
        }
      } else {
        detail::add(m.I_base, Ip, Ic_base);
      }
    }
  });
  // Column i: F = Ic_i S_i carried down the chain, M(j, i) = S_j . F.
  double Mjj[NJ][NJ];
  double Fb[NJ][6];  // floating base: the base rows of column i
  staticFor<NJ>([&](auto I) GIMBALSIM_FLATTEN_LAMBDA {
    constexpr int i = I;
    double F[6];
    detail::inertiaTimesSubspace<V, i>(Ic[i], m.chain[i].axis, F);
    Mjj[i][i] = detail::subspaceDot<V, i>(m.chain[i].axis, F);
    staticFor<i, /*Reverse=*/true>([&](auto J) GIMBALSIM_FLATTEN_LAMBDA {  // j = i .. 1
      constexpr int j = J + 1;
      double XF[6];
      detail::jointForceToParent<V, j>(d.X[j], F, XF);
      for (int c = 0; c < 6; ++c) F[c] = XF[c];
      Mjj[j - 1][i] = detail::subspaceDot<V, j - 1>(m.chain[j - 1].axis, F);
    });
    if constexpr (V::kFloating) {
      detail::jointForceToParent<V, 0>(d.X[0], F, Fb[i]);
    }
  });
  for (int i = 0; i < NJ; ++i) {
    for (int j = 0; j <= i; ++j) d.M(NB + j, NB + i) = d.M(NB + i, NB + j) = Mjj[j][i];
    if constexpr (V::kFloating) {
      for (int k = 0; k < 6; ++k) d.M(k, NB + i) = d.M(NB + i, k) = Fb[i][k];
    }
  }
  if constexpr (V::kFloating) {
    // Ic_base as a 6x6 matrix: [Ibar, [h]x; [h]x^T, m 1]
    const double* h = Ic_base.h;
    const double hx[9] = {0.0, h[2], -h[1], -h[2], 0.0, h[0], h[1], -h[0], 0.0};  // column-major [h]x
    for (int c = 0; c < 3; ++c) {
      for (int r = 0; r < 3; ++r) {
        d.M(r, c) = Ic_base.I[r + 3 * c];
        d.M(r, 3 + c) = hx[r + 3 * c];
        d.M(3 + r, c) = hx[c + 3 * r];
        d.M(3 + r, 3 + c) = r == c ? Ic_base.m : 0.0;
      }
    }
  }
}

}  // namespace gimbalsim
