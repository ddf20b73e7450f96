// Forward kinematics of the chain: joint transforms, motion subspaces, body
// twists (RBDA section 4.3, first pass of the recursive Newton-Euler method).
//
// The chain's joint kinds are fixed per Variant (one group per gimbal joint:
// ideal [R], planar [P, P, R], spatial [P, P, R, R, R]), so every loop over the chain is unrolled at compile time and
// each joint does only its own kind's work: a prismatic joint's rotation is
// the identity, so its transforms reduce to a translation. Every skipped
// operation is a multiplication by an exact 1 or 0 or an addition of an exact
// 0, so the results are bit-identical to the generic 6-D formulas.
#pragma once

#include <cassert>
#include <utility>

#include "gimbalsim/dynamics/data.hpp"

namespace gimbalsim {

/// The joint (0: azimuth, 1: elevation) whose group holds chain joint i, and
/// i's place in that group.
template <class V>
constexpr int chainGroupOf(int i) { return i < V::G2 ? 0 : 1; }
template <class V>
constexpr int chainPlaceInGroup(int i) { return i - V::group(chainGroupOf<V>(i)); }

/// Kind of chain joint i of variant V (Model::finalize builds the same
/// chain): a clearance group is [P, P, R] (planar) or [P, P, R, R, R]
/// (spatial), the first two prismatic.
template <class V>
constexpr JointKind chainJointKind(int i) {
  const bool clearance = V::kind(chainGroupOf<V>(i)) != ClearanceKind::Ideal;
  return (clearance && chainPlaceInGroup<V>(i) < 2) ? JointKind::Prismatic : JointKind::Revolute;
}

/// Chain body i of variant V is massless: every body of a group but its last
/// (the clearance joint's virtual bodies: Model::finalize gives them a zero
/// spatial inertia).
template <class V>
constexpr bool chainBodyMassless(int i) {
  return i != V::group(chainGroupOf<V>(i)) + (chainGroupOf<V>(i) == 0 ? V::N1 : V::N2) - 1;
}

/// Calls f(std::integral_constant<int, i>) for i = 0 .. N-1 (Reverse: N-1 .. 0),
/// so that i is a compile-time constant in the body.
template <int N, bool Reverse = false, class F>
GIMBALSIM_INLINE void staticFor(F&& f) {
  [&]<int... I>(std::integer_sequence<int, I...>) GIMBALSIM_FLATTEN_LAMBDA {
    (f(std::integral_constant<int, Reverse ? N - 1 - I : I>{}), ...);
  }(std::make_integer_sequence<int, N>{});
}

namespace detail {

/// m_C = ^C X_P m_P for a pure translation (R_PC = I): [w; v - r x w].
GIMBALSIM_INLINE void translateMotionToChild(const Vec3& r, const Vec6& m_P, Vec6& m_C) {
  m_C.head<3>() = m_P.head<3>();
  m_C.tail<3>() = m_P.tail<3>() - r.cross(m_P.head<3>());
}

/// out = X^T f of chain joint i (force from body i's to its parent's
/// coordinates), plain arrays; a prismatic joint only translates: [n + r x f; f].
template <class V, int i>
GIMBALSIM_INLINE void jointForceToParent(const Transform& X, const double* f, double* out) {
  if constexpr (chainJointKind<V>(i) == JointKind::Prismatic) {
    double rf[3];
    kernel::cross3(X.r_PC_P.data(), f + 3, rf);
    for (int c = 0; c < 3; ++c) out[c] = f[c] + rf[c];
    for (int c = 0; c < 3; ++c) out[3 + c] = f[3 + c];
  } else {
    kernel::forceToParent(X.R_PC.data(), X.r_PC_P.data(), f, out);
  }
}

/// The same on a Vec6 (rnea.hpp).
template <class V, int i>
GIMBALSIM_INLINE Vec6 jointForceToParent(const Transform& X, const Vec6& f) {
  Vec6 out;
  jointForceToParent<V, i>(X, f.data(), out.data());
  return out;
}

/// X m of chain joint i (motion from the parent's to body i's coordinates).
template <class V, int i>
GIMBALSIM_INLINE Vec6 jointMotionToChild(const Transform& X, const Vec6& m) {
  if constexpr (chainJointKind<V>(i) == JointKind::Prismatic) {
    Vec6 out;
    translateMotionToChild(X.r_PC_P, m, out);
    return out;
  } else {
    return X.motionToChild(m);
  }
}

/// S_i . f for chain joint i, S = [k; 0] or [0; k]: the order of Eigen's
/// 6-vector dot product, (t0 + (t2 + t4)) + (t1 + (t3 + t5)), with its three
/// exact zero terms dropped.
template <class V, int i>
GIMBALSIM_INLINE double subspaceDot(const Vec3& k, const double* f) {
  constexpr int o = chainJointKind<V>(i) == JointKind::Revolute ? 0 : 3;
  return (k.x() * f[o] + k.z() * f[o + 2]) + k.y() * f[o + 1];
}
template <class V, int i>
GIMBALSIM_INLINE double subspaceDot(const Vec3& k, const Vec6& f) {
  return subspaceDot<V, i>(k, f.data());
}

}  // namespace detail

template <class V, class Q, class W>
GIMBALSIM_FLATTEN void kinematics(const Model& m, Data<V>& d, const Eigen::MatrixBase<Q>& q,
                const Eigen::MatrixBase<W>& v) {
  constexpr int QJ = State<V>::QJ, NB = V::NB;
  if constexpr (V::kFloating) d.v_base = v.template head<6>();
  staticFor<V::NJ>([&](auto I) GIMBALSIM_FLATTEN_LAMBDA {
    constexpr int i = I;
    const Model::ChainJoint& J = m.chain[i];
    assert(J.kind == chainJointKind<V>(i));
    Transform& X = d.X[i];
    const double qi = q(QJ + i), qdi = v(NB + i);
    Vec6& vi = d.v[i];
    if constexpr (chainJointKind<V>(i) == JointKind::Revolute) {
      X.R_PC = axisAngle(J.axis, qi);
      X.r_PC_P = J.origin;
      if constexpr (i > 0) {
        vi = X.motionToChild(d.v[i - 1]);
      } else if constexpr (V::kFloating) {
        vi = X.motionToChild(d.v_base);
      } else {
        vi.setZero();
      }
      vi.template head<3>() += J.axis * qdi;  // + S qd
    } else {
      X.R_PC.setIdentity();
      X.r_PC_P = J.origin + qi * J.axis;
      if constexpr (i > 0) {
        detail::translateMotionToChild(X.r_PC_P, d.v[i - 1], vi);
      } else if constexpr (V::kFloating) {
        detail::translateMotionToChild(X.r_PC_P, d.v_base, vi);
      } else {
        vi.setZero();
      }
      vi.template tail<3>() += J.axis * qdi;  // + S qd
    }
  });
}

}  // namespace gimbalsim
