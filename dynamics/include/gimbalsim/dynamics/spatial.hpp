// Spatial (6-D) algebra in Featherstone's convention: motion vectors are
// [angular; linear], force vectors [moment; force], all in the coordinates of
// one body frame. Featherstone, "Rigid Body Dynamics Algorithms" (RBDA), ch. 2.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

/// Forces inlining of the small hot-path helpers (GCC/Clang): at -O3 GCC
/// otherwise keeps many of these 6-D helpers out of line.
#if defined(__GNUC__)
#define GIMBALSIM_INLINE inline __attribute__((always_inline))
#else
#define GIMBALSIM_INLINE inline
#endif
/// Flattens the derivative's stages into one body. The sanitizer and fuzz
/// builds define GIMBALSIM_NO_FLATTEN (CMakeLists.txt): flattened and
/// instrumented, one spatial shape took over 10 minutes to compile, 33 s without.
#if defined(__GNUC__) && !defined(GIMBALSIM_NO_FLATTEN)
#define GIMBALSIM_FLATTEN __attribute__((flatten))
/// Clang before LLVM 17 flattens one level only: the lambdas a stage passes
/// to staticFor stayed calls (10 % of a clearance derivative). Marking them
/// gives both compilers the one body.
#define GIMBALSIM_FLATTEN_LAMBDA __attribute__((always_inline))
#else
#define GIMBALSIM_FLATTEN
#define GIMBALSIM_FLATTEN_LAMBDA
#endif

namespace gimbalsim {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

/// Skew-symmetric cross-product matrix: skew(a) * b == a x b.
GIMBALSIM_INLINE Mat3 skew(const Vec3& a) {
  Mat3 s;
  s << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return s;
}

/// Exact-order 3-D kernels. Eigen (3.4, SSE2) evaluates a 3x3 column-major
/// matrix times a vector as (t0 + t1) + t2 in rows 0 and 1 and t0 + (t1 + t2)
/// in row 2 (two rows by packet, the last by a scalar reduction), and a
/// transposed matrix (row-major) times a vector as (t0 + t1) + t2 in every
/// row. The scalar kernels below reproduce those orders, so replacing the
/// Eigen expressions by them leaves every result bit-identical while the
/// compiler sees plain scalar code without packet shuffles.
namespace kernel {

/// y = A x, A column-major 3x3 as a plain array (Eigen's order, see above).
GIMBALSIM_INLINE void mul3(const double* A, double x0, double x1, double x2, double* y) {
  y[0] = (A[0] * x0 + A[3] * x1) + A[6] * x2;
  y[1] = (A[1] * x0 + A[4] * x1) + A[7] * x2;
  y[2] = A[2] * x0 + (A[5] * x1 + A[8] * x2);
}

/// y = A^T x (Eigen's order for a transposed left-hand side).
GIMBALSIM_INLINE void mul3T(const double* A, double x0, double x1, double x2, double* y) {
  y[0] = (A[0] * x0 + A[1] * x1) + A[2] * x2;
  y[1] = (A[3] * x0 + A[4] * x1) + A[5] * x2;
  y[2] = (A[6] * x0 + A[7] * x1) + A[8] * x2;
}

/// y = a x b (Eigen's cross()).
GIMBALSIM_INLINE void cross3(const double* a, const double* b, double* y) {
  const double y0 = a[1] * b[2] - a[2] * b[1];
  const double y1 = a[2] * b[0] - a[0] * b[2];
  const double y2 = a[0] * b[1] - a[1] * b[0];
  y[0] = y0, y[1] = y1, y[2] = y2;
}

// Spatial operations on plain 6-arrays [angular; linear]. The hot path keeps
// its vectors in plain arrays written and read by scalar code: mixing scalar
// stores with Eigen's 16-byte packet loads of the same data stalls store
// forwarding. out must not alias the inputs.

/// out = ^C X_P m = [R^T w; R^T (v - r x w)] (R = R_PC, r = r_PC_P).
GIMBALSIM_INLINE void motionToChild(const double* R, const double* r, const double* m, double* out) {
  double rw[3];
  mul3T(R, m[0], m[1], m[2], out);
  cross3(r, m, rw);
  mul3T(R, m[3] - rw[0], m[4] - rw[1], m[5] - rw[2], out + 3);
}

/// out = ^P X_C^* f = [R n + r x (R f); R f].
GIMBALSIM_INLINE void forceToParent(const double* R, const double* r, const double* f, double* out) {
  double rf[3];
  mul3(R, f[3], f[4], f[5], out + 3);
  mul3(R, f[0], f[1], f[2], out);
  cross3(r, out + 3, rf);
  out[0] += rf[0], out[1] += rf[1], out[2] += rf[2];
}

/// out = v x* f = [w x n + v_o x f; w x f].
GIMBALSIM_INLINE void crossForce(const double* v, const double* f, double* out) {
  double a[3], b[3];
  cross3(v, f, a);
  cross3(v + 3, f + 3, b);
  out[0] = a[0] + b[0], out[1] = a[1] + b[1], out[2] = a[2] + b[2];
  cross3(v, f + 3, out + 3);
}

/// out = I v = [Ibar w + h x v_o; m v_o - h x w] for I = (m, h, Ibar).
GIMBALSIM_INLINE void inertiaTimes(double m, const double* h, const double* Ibar, const double* v,
                                   double* out) {
  double hv[3], hw[3];
  mul3(Ibar, v[0], v[1], v[2], out);
  cross3(h, v + 3, hv);
  cross3(h, v, hw);
  out[0] += hv[0], out[1] += hv[1], out[2] += hv[2];
  out[3] = m * v[3] - hw[0], out[4] = m * v[4] - hw[1], out[5] = m * v[5] - hw[2];
}

}  // namespace kernel

/// Rotation by angle th [rad] about unit axis k (Rodrigues' formula
/// c I + s [k]x + (1 - c) k k^T with c = cos(th), s = sin(th)), written out
/// entry by entry: the same floating-point operations, in the same order, as
/// the matrix expression, so the result is bit-identical to it, without the
/// temporaries.
GIMBALSIM_INLINE Mat3 axisAngle(const Vec3& k, double th) {
  const double c = std::cos(th), s = std::sin(th);
  const double t = 1.0 - c;
  Mat3 M;
  double* R = M.data();
  const double tx = t * k.x(), ty = t * k.y(), tz = t * k.z();
  R[0] = c + tx * k.x();            // (0, 0)
  R[4] = c + ty * k.y();            // (1, 1)
  R[8] = c + tz * k.z();            // (2, 2)
  R[3] = s * -k.z() + tx * k.y();   // (0, 1)
  R[1] = s * k.z() + ty * k.x();    // (1, 0)
  R[6] = s * k.y() + tx * k.z();    // (0, 2)
  R[2] = s * -k.y() + tz * k.x();   // (2, 0)
  R[7] = s * -k.x() + ty * k.z();   // (1, 2)
  R[5] = s * k.x() + tz * k.y();    // (2, 1)
  return M;
}

/// Rigid transform between a parent frame P and a child frame C.
/// R_PC rotates child coordinates into parent coordinates; r_PC_P is the child
/// origin in parent coordinates [m].
struct Transform {
  Mat3 R_PC = Mat3::Identity();
  Vec3 r_PC_P = Vec3::Zero();

  /// Motion vector from parent to child coordinates (RBDA eq. 2.24):
  /// [E w; E (v - r x w)] with E = R_PC^T.
  GIMBALSIM_INLINE Vec6 motionToChild(const Vec6& m_P) const {
    Vec6 out;
    kernel::motionToChild(R_PC.data(), r_PC_P.data(), m_P.data(), out.data());
    return out;
  }
};

/// Force cross product v x* f (RBDA eq. 2.32).
GIMBALSIM_INLINE Vec6 crossForce(const Vec6& v, const Vec6& f) {
  Vec6 out;
  kernel::crossForce(v.data(), f.data(), out.data());
  return out;
}

/// Spatial inertia about a frame origin in its compact form (RBDA eq. 2.63):
/// mass m [kg], first moment h = m c [kg m], rotational inertia Ibar about the
/// origin [kg m^2]. Products and frame changes cost 3x3 work, not 6x6.
struct SpatialInertia {
  double m = 0.0;
  Vec3 h = Vec3::Zero();
  Mat3 Ibar = Mat3::Zero();

  static SpatialInertia fromBody(double mass, const Vec3& c, const Mat3& Ic) {
    const Mat3 cx = skew(c);
    return {mass, mass * c, Ic - mass * cx * cx};
  }
  /// Momentum I v of twist v = [omega; v_o]: [Ibar w + h x v_o; m v_o - h x w].
  GIMBALSIM_INLINE Vec6 operator*(const Vec6& v) const {
    Vec6 out;
    kernel::inertiaTimes(m, h.data(), Ibar.data(), v.data(), out.data());
    return out;
  }
};

namespace detail {

/// Row j of the forward substitution L y = b into x: (b_j - sum_{k<j} L(j, k)
/// x_k) / l, with l = L(j, j).
template <int N>
GIMBALSIM_INLINE void forwardSubstituteRow(const Eigen::Matrix<double, N, N>& L, int j, double bj, double l,
                                           Eigen::Matrix<double, N, 1>& x) {
  double y = bj;
#pragma GCC unroll 16
  for (int k = 0; k < j; ++k) y -= L(j, k) * x(k);
  x(j) = y / l;
}

/// Back substitution L^T x = y in place (x holds y on entry).
template <int N>
GIMBALSIM_INLINE void backSubstitute(const Eigen::Matrix<double, N, N>& L, Eigen::Matrix<double, N, 1>& x) {
#pragma GCC unroll 16
  for (int i = N - 1; i >= 0; --i) {
    double s = x(i);
#pragma GCC unroll 16
    for (int k = i + 1; k < N; ++k) s -= L(k, i) * x(k);
    x(i) = s / L(i, i);
  }
}

}  // namespace detail

/// Solves A x = b for symmetric positive definite A by Cholesky (forward
/// dynamics uses mass_factor.hpp; this dense solve is its cross-check), reading A's
/// lower triangle and writing the lower factor into L (L may be A itself),
/// b(j) given by a callable (it may read x: b(j) is read before x(j) is
/// written). Fixed size, fully unrolled (the loop bounds are compile-time
/// constants); returns false when A is not positive definite (x is then
/// meaningless). Each entry is computed by the same operations in the same
/// order as the textbook left-looking loops; the forward substitution of row
/// j is moved up to just after column j is factored, so it overlaps the
/// factorisation (the solve is latency-bound: a sqrt and a division per
/// column, a division per row of each substitution).
template <int N, class B>
GIMBALSIM_INLINE bool choleskySolve(const Eigen::Matrix<double, N, N>& A, Eigen::Matrix<double, N, N>& L,
                                    const B& b, Eigen::Matrix<double, N, 1>& x) {
  bool ok = true;
#pragma GCC unroll 16
  for (int j = 0; j < N; ++j) {
    double d = A(j, j);
#pragma GCC unroll 16
    for (int k = 0; k < j; ++k) d -= L(j, k) * L(j, k);
    ok = ok && d > 0.0;
    const double l = std::sqrt(d);
    L(j, j) = l;
    const double il = 1.0 / l;
    detail::forwardSubstituteRow(L, j, b(j), l, x);  // L y = b, row j (needs only columns 0..j)
#pragma GCC unroll 16
    for (int i = j + 1; i < N; ++i) {
      double s = A(i, j);
#pragma GCC unroll 16
      for (int k = 0; k < j; ++k) s -= L(i, k) * L(j, k);
      L(i, j) = s * il;
    }
  }
  if (!ok) return false;
  detail::backSubstitute(L, x);
  return true;
}

}  // namespace gimbalsim
