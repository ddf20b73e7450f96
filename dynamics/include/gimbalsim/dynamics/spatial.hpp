// Spatial (6-D) algebra in Featherstone's convention: motion vectors are
// [angular; linear], force vectors [moment; force], all in the coordinates of
// one body frame. Featherstone, "Rigid Body Dynamics Algorithms" (RBDA), ch. 2.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace gimbalsim {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat3 = Eigen::Matrix3d;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Quat = Eigen::Quaterniond;

/// Skew-symmetric cross-product matrix: skew(a) * b == a x b.
inline Mat3 skew(const Vec3& a) {
  Mat3 s;
  s << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return s;
}

/// Rotation by angle th [rad] about unit axis k (Rodrigues' formula).
inline Mat3 axisAngle(const Vec3& k, double th) {
  const double c = std::cos(th), s = std::sin(th);
  return c * Mat3::Identity() + s * skew(k) + (1.0 - c) * k * k.transpose();
}

/// Rigid transform between a parent frame P and a child frame C.
/// R_PC rotates child coordinates into parent coordinates; r_PC_P is the child
/// origin in parent coordinates [m].
struct Transform {
  Mat3 R_PC = Mat3::Identity();
  Vec3 r_PC_P = Vec3::Zero();

  /// Motion vector from parent to child coordinates (RBDA eq. 2.24).
  Vec6 motionToChild(const Vec6& m_P) const {
    Vec6 out;
    out.head<3>().noalias() = R_PC.transpose() * m_P.head<3>();
    out.tail<3>().noalias() = R_PC.transpose() * (m_P.tail<3>() - r_PC_P.cross(m_P.head<3>()));
    return out;
  }
  /// Force vector from child to parent coordinates (transpose of the above).
  Vec6 forceToParent(const Vec6& f_C) const {
    Vec6 out;
    out.tail<3>().noalias() = R_PC * f_C.tail<3>();
    out.head<3>().noalias() = R_PC * f_C.head<3>();
    out.head<3>() += r_PC_P.cross(out.tail<3>());
    return out;
  }
  /// 6x6 matrix of motionToChild (^C X_P).
  Mat6 motionMatrixToChild() const {
    Mat6 X;
    const Mat3 E = R_PC.transpose();
    X.topLeftCorner<3, 3>() = E;
    X.topRightCorner<3, 3>().setZero();
    X.bottomLeftCorner<3, 3>().noalias() = -E * skew(r_PC_P);
    X.bottomRightCorner<3, 3>() = E;
    return X;
  }
};

/// Motion cross product v x m (RBDA eq. 2.31).
inline Vec6 crossMotion(const Vec6& v, const Vec6& m) {
  Vec6 out;
  out.head<3>() = v.head<3>().cross(m.head<3>());
  out.tail<3>() = v.head<3>().cross(m.tail<3>()) + v.tail<3>().cross(m.head<3>());
  return out;
}

/// Force cross product v x* f (RBDA eq. 2.32).
inline Vec6 crossForce(const Vec6& v, const Vec6& f) {
  Vec6 out;
  out.head<3>() = v.head<3>().cross(f.head<3>()) + v.tail<3>().cross(f.tail<3>());
  out.tail<3>() = v.head<3>().cross(f.tail<3>());
  return out;
}

/// Spatial inertia about a frame origin of a body of mass m [kg], centre of
/// mass c [m] and rotational inertia Ic [kg m^2] about the centre of mass,
/// all in that frame (RBDA eq. 2.63).
inline Mat6 spatialInertia(double m, const Vec3& c, const Mat3& Ic) {
  Mat6 I;
  const Mat3 cx = skew(c);
  I.topLeftCorner<3, 3>() = Ic + m * cx * cx.transpose();
  I.topRightCorner<3, 3>() = m * cx;
  I.bottomLeftCorner<3, 3>() = m * cx.transpose();
  I.bottomRightCorner<3, 3>() = m * Mat3::Identity();
  return I;
}

}  // namespace gimbalsim

namespace gimbalsim {

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
  /// Momentum I v of twist v = [omega; v_o].
  Vec6 operator*(const Vec6& v) const {
    Vec6 out;
    out.head<3>().noalias() = Ibar * v.head<3>();
    out.head<3>() += h.cross(v.tail<3>());
    out.tail<3>() = m * v.tail<3>() - h.cross(v.head<3>());
    return out;
  }
  SpatialInertia& operator+=(const SpatialInertia& o) {
    m += o.m;
    h += o.h;
    Ibar += o.Ibar;
    return *this;
  }
  /// The same inertia about the parent origin in parent coordinates
  /// (X^T I X for the motion transform X = ^C X_P).
  SpatialInertia toParent(const Transform& X) const {
    SpatialInertia p;
    const Vec3 Rh = X.R_PC * h;
    const Mat3 rx = skew(X.r_PC_P), Rhx = skew(Rh);
    p.m = m;
    p.h = Rh + m * X.r_PC_P;
    p.Ibar.noalias() = X.R_PC * Ibar * X.R_PC.transpose();
    p.Ibar -= m * rx * rx + rx * Rhx + Rhx * rx;
    return p;
  }
  Mat6 matrix() const {
    Mat6 I;
    I.topLeftCorner<3, 3>() = Ibar;
    I.topRightCorner<3, 3>() = skew(h);
    I.bottomLeftCorner<3, 3>() = skew(h).transpose();
    I.bottomRightCorner<3, 3>() = m * Mat3::Identity();
    return I;
  }
};

/// Solves A x = b in place for symmetric positive definite A (Cholesky,
/// lower factor written over A). Fixed size, unrolled by the compiler; returns
/// false when A is not positive definite (x is then meaningless).
template <int N>
bool choleskySolveInPlace(Eigen::Matrix<double, N, N>& A, Eigen::Matrix<double, N, 1>& x) {
  for (int j = 0; j < N; ++j) {
    double d = A(j, j);
    for (int k = 0; k < j; ++k) d -= A(j, k) * A(j, k);
    if (!(d > 0.0)) return false;
    const double l = std::sqrt(d);
    A(j, j) = l;
    const double il = 1.0 / l;
    for (int i = j + 1; i < N; ++i) {
      double s = A(i, j);
      for (int k = 0; k < j; ++k) s -= A(i, k) * A(j, k);
      A(i, j) = s * il;
    }
  }
  for (int i = 0; i < N; ++i) {  // L y = b
    double s = x(i);
    for (int k = 0; k < i; ++k) s -= A(i, k) * x(k);
    x(i) = s / A(i, i);
  }
  for (int i = N - 1; i >= 0; --i) {  // L^T x = y
    double s = x(i);
    for (int k = i + 1; k < N; ++k) s -= A(k, i) * x(k);
    x(i) = s / A(i, i);
  }
  return true;
}

}  // namespace gimbalsim
