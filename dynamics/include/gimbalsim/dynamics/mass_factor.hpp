// The joint-space inertia M's factorisation, specialised to this tree: the
// floating base's 6x6 block is the whole system's composite rigid-body
// inertia, inverted in closed form about its centre of mass, and the NJ chain
// coordinates are solved by the L D L^T factors of the small Schur
// complement S = Mjj - Mjb Mbb^-1 Mbj (docs/MODEL.md 3.6). A dense Cholesky
// of the (6 + NJ)-square M spends most of its work, and its latency chain of
// square roots and divisions, on the base block, whose inverse is known.
// A fixed base has no base block: S = Mjj.
#pragma once

#include "gimbalsim/dynamics/spatial.hpp"

namespace gimbalsim {

template <class V>
struct MassFactor {
  static constexpr int NB = V::NB, NJ = V::NJ, NV = V::NV;
  using VecV = Eigen::Matrix<double, NV, 1>;
  // Floating base, Mbb = [Ibar, [h]x; [h]x^T, m 1] about the base origin in base coordinates:
  double inv_m = 0.0;                        ///< 1 / total mass [1/kg]
  Vec3 c_B = Vec3::Zero();                   ///< centre of mass h / m, base coordinates [m]
  Mat3 Icom_inv = Mat3::Zero();              ///< inverse rotational inertia about the centre of mass [1/(kg m^2)]
  Eigen::Matrix<double, 6, NJ> Y = Eigen::Matrix<double, 6, NJ>::Zero();  ///< Mbb^-1 Mbj
  Eigen::Matrix<double, NJ, NJ> L = Eigen::Matrix<double, NJ, NJ>::Zero();  ///< S = L D L^T: L unit lower
  Eigen::Matrix<double, NJ, 1> inv_d = Eigen::Matrix<double, NJ, 1>::Zero();  ///< 1 / D(j, j)
  bool ok = false;  ///< M was positive definite when factored
};

namespace detail {

/// x = Mbb^-1 [n; f] for the base block: omega = Icom^-1 (n - c x f),
/// v = f / m + c x omega (the base block's two block rows, solved for v first).
template <class V>
GIMBALSIM_INLINE void baseBlockSolve(const MassFactor<V>& F, const double* nf, double* x) {
  const Vec3 n(nf[0], nf[1], nf[2]), f(nf[3], nf[4], nf[5]);
  const Vec3 w = F.Icom_inv * (n - F.c_B.cross(f));
  const Vec3 v = F.inv_m * f + F.c_B.cross(w);
  for (int k = 0; k < 3; ++k) x[k] = w(k), x[3 + k] = v(k);
}

/// Inverse of a symmetric 3x3 matrix by its adjugate; false unless positive
/// definite (leading minors > 0).
GIMBALSIM_INLINE bool symmetricInverse3(const Mat3& A, Mat3& inv) {
  const double c00 = A(1, 1) * A(2, 2) - A(1, 2) * A(1, 2);
  const double c01 = A(0, 2) * A(1, 2) - A(0, 1) * A(2, 2);
  const double c02 = A(0, 1) * A(1, 2) - A(0, 2) * A(1, 1);
  const double det = A(0, 0) * c00 + A(0, 1) * c01 + A(0, 2) * c02;
  const double minor2 = A(0, 0) * A(1, 1) - A(0, 1) * A(0, 1);
  const double id = 1.0 / det;
  inv(0, 0) = c00 * id;
  inv(0, 1) = inv(1, 0) = c01 * id;
  inv(0, 2) = inv(2, 0) = c02 * id;
  inv(1, 1) = (A(0, 0) * A(2, 2) - A(0, 2) * A(0, 2)) * id;
  inv(1, 2) = inv(2, 1) = (A(0, 2) * A(0, 1) - A(0, 0) * A(1, 2)) * id;
  inv(2, 2) = minor2 * id;
  return A(0, 0) > 0.0 && minor2 > 0.0 && det > 0.0;
}

/// S = L D L^T for symmetric S (its lower triangle): L unit lower
/// triangular, and the reciprocals of D's diagonal. No square root sits on
/// the latency chain, one division per column, and the solves multiply
/// where a division would sit. False unless S is positive definite (every
/// pivot > 0). Kept apart from spatial.hpp's dense choleskySolve on purpose:
/// that one is the tests' independent cross-check of this solve.
template <int N>
GIMBALSIM_INLINE bool ldltFactor(const Eigen::Matrix<double, N, N>& S, Eigen::Matrix<double, N, N>& L,
                                 Eigen::Matrix<double, N, 1>& inv_d) {
  bool ok = true;
  double W[N][N];  // W[i][k] = L(i, k) d_k, k < i
#pragma GCC unroll 16
  for (int j = 0; j < N; ++j) {
    double d = S(j, j);
#pragma GCC unroll 16
    for (int k = 0; k < j; ++k) d -= W[j][k] * L(j, k);
    ok = ok && d > 0.0;
    const double id = 1.0 / d;
    inv_d(j) = id;
    L(j, j) = 1.0;
#pragma GCC unroll 16
    for (int i = j + 1; i < N; ++i) {
      double s = S(i, j);
#pragma GCC unroll 16
      for (int k = 0; k < j; ++k) s -= W[i][k] * L(j, k);
      W[i][j] = s;
      L(i, j) = s * id;
    }
  }
  return ok;
}

/// x = (L D L^T)^-1 x in place, L and 1/D from ldltFactor().
template <int N>
GIMBALSIM_INLINE void ldltSolveInPlace(const Eigen::Matrix<double, N, N>& L,
                                       const Eigen::Matrix<double, N, 1>& inv_d,
                                       Eigen::Matrix<double, N, 1>& x) {
  double z[N];  // L z = x, then D^-1 z
#pragma GCC unroll 16
  for (int j = 0; j < N; ++j) {
    double y = x(j);
#pragma GCC unroll 16
    for (int k = 0; k < j; ++k) y -= L(j, k) * z[k];
    z[j] = y;
  }
#pragma GCC unroll 16
  for (int j = 0; j < N; ++j) z[j] *= inv_d(j);
#pragma GCC unroll 16
  for (int i = N - 1; i >= 0; --i) {
    double y = z[i];
#pragma GCC unroll 16
    for (int k = i + 1; k < N; ++k) y -= L(k, i) * z[k];
    z[i] = y;
    x(i) = y;
  }
}

}  // namespace detail

/// Factors M (its lower triangle and the base block as crba() writes it).
/// Returns false (and F.ok = false) unless M is positive definite.
template <class V>
GIMBALSIM_INLINE bool factorMass(const Eigen::Matrix<double, V::NV, V::NV>& M, MassFactor<V>& F) {
  constexpr int NB = V::NB, NJ = V::NJ;
  bool ok = true;
  Eigen::Matrix<double, NJ, NJ> S = M.template bottomRightCorner<NJ, NJ>();
  if constexpr (V::kFloating) {
    const double mass = M(3, 3);
    const Vec3 h(M(2, 4), M(0, 5), M(1, 3));  // the [h]x block's entries (crba())
    F.inv_m = 1.0 / mass;
    F.c_B = F.inv_m * h;
    // Icom = Ibar + [h]x [h]x / m = Ibar + (h h^T - |h|^2 1) / m
    Mat3 Icom = M.template topLeftCorner<3, 3>() + F.inv_m * (h * h.transpose());
    Icom.diagonal().array() -= F.inv_m * h.squaredNorm();
    ok = mass > 0.0 && detail::symmetricInverse3(Icom, F.Icom_inv);
    for (int j = 0; j < NJ; ++j) {
      detail::baseBlockSolve(F, M.col(NB + j).data(), F.Y.col(j).data());
    }
    // S = Mjj - Mbj^T Y (lower triangle is all the Cholesky reads)
    for (int j = 0; j < NJ; ++j) {
      for (int i = j; i < NJ; ++i) S(i, j) -= M.col(NB + i).template head<6>().dot(F.Y.col(j));
    }
  }
  ok = detail::ldltFactor<NJ>(S, F.L, F.inv_d) && ok;
  F.ok = ok;
  return ok;
}

/// x = M^-1 b with M factored by factorMass(); x may be b (b is read in full first).
template <class V>
GIMBALSIM_INLINE void solveMass(const MassFactor<V>& F, const typename MassFactor<V>::VecV& b,
                                typename MassFactor<V>::VecV& x) {
  constexpr int NB = V::NB, NJ = V::NJ;
  Eigen::Matrix<double, NJ, 1> xj = b.template tail<NJ>();
  double y[6];
  if constexpr (V::kFloating) {
    detail::baseBlockSolve(F, b.data(), y);
    // Mjb Mbb^-1 = Y^T (Mbb is symmetric)
    xj.noalias() -= F.Y.transpose() * b.template head<6>();
  }
  detail::ldltSolveInPlace<NJ>(F.L, F.inv_d, xj);
  x.template tail<NJ>() = xj;
  if constexpr (V::kFloating) {
    const Vec6 xb = Eigen::Map<const Vec6>(y) - F.Y * xj;
    x.template head<NB>() = xb;
  }
}

}  // namespace gimbalsim
