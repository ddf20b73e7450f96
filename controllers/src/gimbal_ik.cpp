#include "gimbalsim/controllers/gimbal_ik.hpp"

#include <cmath>

#include "gimbalsim/pointing/target_profile.hpp"

namespace gimbalsim::controllers {
namespace {

constexpr double kTwoPi = 2.0 * M_PI;

/// The representative of angle a (mod 2 pi) nearest to ref [rad].
double nearest(double a, double ref) noexcept { return a + kTwoPi * std::round((ref - a) / kTwoPi); }

/// Least-squares step of J x = r; with freeze_azimuth (or a rank-deficient J)
/// only the second column fits and x(0) = 0.
Vec2 leastSquares(const Mat32& J, const Vec3& r, bool freeze_azimuth) noexcept {
  const double a00 = J.col(0).squaredNorm(), a01 = J.col(0).dot(J.col(1)), a11 = J.col(1).squaredNorm();
  const double det = a00 * a11 - a01 * a01;
  if (!freeze_azimuth && det > 1e-12 * a00 * a11) {
    const double r0 = J.col(0).dot(r), r1 = J.col(1).dot(r);
    return {(a11 * r0 - a01 * r1) / det, (a00 * r1 - a01 * r0) / det};
  }
  return {0.0, a11 > 0.0 ? J.col(1).dot(r) / a11 : 0.0};
}

/// Closed form (k1 _|_ k2, b _|_ k2): the branch and 2 pi representatives
/// nearest to prev; singular: azimuth kept, elevation in the plane (u, e3).
Vec2 closedForm(const GimbalGeometry& g, const Vec3& d, const Vec2& prev, bool singular) noexcept {
  const double d1 = d.dot(g.e1), d2 = d.dot(g.e2), d3 = d.dot(g.e3);
  if (singular) {
    const double t1 = prev(0);
    const double du = std::cos(t1) * d1 + std::sin(t1) * d2;
    return {t1, nearest(std::atan2(-d3, du) - g.phi0, prev(1))};
  }
  const double rho = std::hypot(d1, d2);
  const Vec2 a{nearest(std::atan2(d2, d1), prev(0)), nearest(std::atan2(-d3, rho) - g.phi0, prev(1))};
  const Vec2 b{nearest(std::atan2(-d2, -d1), prev(0)), nearest(std::atan2(-d3, -rho) - g.phi0, prev(1))};
  return (a - prev).squaredNorm() <= (b - prev).squaredNorm() ? a : b;
}

}  // namespace

GimbalGeometry gimbalGeometry(const Model& m) noexcept {
  return gimbalGeometry(m.k1_B, m.k2_S1, m.boresight_S2);
}

GimbalGeometry gimbalGeometry(const Vec3& k1_B, const Vec3& k2_S1, const Vec3& boresight_S2) noexcept {
  GimbalGeometry g;
  g.k1_B = k1_B.normalized();
  g.k2_S1 = k2_S1.normalized();
  g.b_S2 = boresight_S2.normalized();
  g.closed_form = std::abs(g.k1_B.dot(g.k2_S1)) < kOrthogonalTol && std::abs(g.b_S2.dot(g.k2_S1)) < kOrthogonalTol;
  if (g.closed_form) {
    g.e3 = g.k1_B;
    g.e2 = g.k2_S1;
    g.e1 = g.e2.cross(g.e3);
    g.phi0 = std::atan2(-g.b_S2.dot(g.e3), g.b_S2.dot(g.e1));
  }
  return g;
}

Vec3 boresightB(const GimbalGeometry& g, const Vec2& theta) noexcept {
  return pointing::gimbalBoresight(g.k1_B, g.k2_S1, g.b_S2, theta(0), theta(1));
}

Mat32 boresightJacobian(const GimbalGeometry& g, const Vec2& theta) noexcept {
  const Mat3 R1 = axisAngle(g.k1_B, theta(0));
  const Vec3 b = boresightB(g, theta);
  Mat32 J;
  J.col(0) = g.k1_B.cross(b);
  J.col(1) = (R1 * g.k2_S1).cross(b);
  return J;
}

Vec3 boresightCurvature(const GimbalGeometry& g, const Vec2& theta, const Vec2& dtheta) noexcept {
  const Vec3 b = boresightB(g, theta);
  const Vec3 k2 = axisAngle(g.k1_B, theta(0)) * g.k2_S1;  // joint 2 axis, base frame
  const Vec3 b_dot = dtheta(0) * g.k1_B.cross(b) + dtheta(1) * k2.cross(b);
  const Vec3 k2_dot = dtheta(0) * g.k1_B.cross(k2);
  return dtheta(0) * g.k1_B.cross(b_dot) + dtheta(1) * (k2_dot.cross(b) + k2.cross(b_dot));
}

IkSolution solveAngles(const GimbalGeometry& g, const Vec3& d_B, const Vec2& theta_prev,
                       const IkOptions& o) noexcept {
  const Vec3 d = d_B.normalized();
  IkSolution s;
  s.singular = g.k1_B.cross(d).norm() < o.singular_tol;
  if (g.closed_form) {
    s.theta = closedForm(g, d, theta_prev, s.singular);
  } else {
    // Gauss-Newton on min |b_B(theta) - d|^2 from the previous solution.
    s.theta = theta_prev;
    s.converged = false;
    while (s.iterations < o.max_iterations && !s.converged) {
      const Vec2 step = leastSquares(boresightJacobian(g, s.theta), d - boresightB(g, s.theta), s.singular);
      s.theta += step;
      ++s.iterations;
      s.converged = step.cwiseAbs().maxCoeff() < o.step_tol;
    }
  }
  s.over_the_top = g.closed_form && std::cos(s.theta(1) + g.phi0) < 0.0;
  s.residual = pointing::pointingError(boresightB(g, s.theta), d);
  return s;
}

Vec2 solveRates(const GimbalGeometry& g, const Vec2& theta, const Vec3& d_B_dot, const IkOptions& o) noexcept {
  const Mat32 J = boresightJacobian(g, theta);
  return leastSquares(J, d_B_dot, J.col(0).norm() < o.singular_tol);
}

Vec2 solveAccelerations(const GimbalGeometry& g, const Vec2& theta, const Vec2& dtheta, const Vec3& d_B_ddot,
                        const IkOptions& o) noexcept {
  const Mat32 J = boresightJacobian(g, theta);
  return leastSquares(J, d_B_ddot - boresightCurvature(g, theta, dtheta), J.col(0).norm() < o.singular_tol);
}

LosInBase losInBase(const Vec3& d_W, const Vec3& dd_W, const Vec3& ddd_W, const Mat3& R_WB, const Vec3& omega_B,
                    const Vec3& alpha_B) noexcept {
  LosInBase l = losInBase(d_W, dd_W, R_WB, omega_B);
  l.d_B_ddot = R_WB.transpose() * ddd_W - omega_B.cross(R_WB.transpose() * dd_W) - alpha_B.cross(l.d_B) -
               omega_B.cross(l.d_B_dot);
  return l;
}

LosInBase losInBase(const Vec3& d_W, const Vec3& dd_W, const Mat3& R_WB, const Vec3& omega_B) noexcept {
  LosInBase l;
  l.d_B = R_WB.transpose() * d_W;
  l.d_B_dot = R_WB.transpose() * dd_W - omega_B.cross(l.d_B);
  return l;
}

}  // namespace gimbalsim::controllers
