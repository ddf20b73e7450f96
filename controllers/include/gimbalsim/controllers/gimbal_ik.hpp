// Inverse kinematics of the two-axis gimbal: which joint angles (theta1
// azimuth, theta2 elevation) put the antenna boresight along a wanted line of
// sight, and which joint rates follow it. A building block of the inertial
// pointing controller (inertial_reference.cpp). Pure, allocation-free,
// noexcept; fixed-size Eigen types only.
//
// Frames (docs/MODEL.md 1.3, 8.2): B base, S1 shaft 1, S2 shaft 2, W inertial,
// all parallel at q = 0. The boresight in the BASE frame is
//   b_B(theta) = Rot(k1_B, theta1) Rot(k2_S1, theta2) boresight_S2
// (the clearance joint's eccentricity moves the antenna but does not turn it,
// so it plays no part). Its Jacobian (3x2, base frame, per radian):
//   J = [ k1_B x b_B ,  (Rot(k1_B, theta1) k2_S1) x b_B ].
//
// Angles. When k1 is perpendicular to k2 and the boresight is perpendicular
// to k2 (the paper's geometry: z, y, x), with e1 = k2 x k1, e2 = k2, e3 = k1
// and phi0 = atan2(-b.e3, b.e1):
//   b_B = cos(el) (cos(theta1) e1 + sin(theta1) e2) - sin(el) e3,  el = theta2 + phi0,
// so el = atan2(-d.e3, +-rho), theta1 = atan2(+-d.e2, +-d.e1), rho = |k1 x d|:
// two branches (the second one "over the top", cos(el) < 0), each defined
// modulo 2 pi per angle. Of the four nearest representatives the one closest
// to the previous solution is returned, so a continuous d gives continuous
// angles. Any other geometry (k2 tilted, boresight not perpendicular to k2):
// Gauss-Newton on min |b_B(theta) - d_B|^2 (a 2x2 normal-equation solve per
// step) from the previous solution, at most max_iterations steps, quadratic
// convergence near a reachable d (zero residual); the branch is the one the
// previous solution lies in. An unreachable d gives the least-squares angles
// and a residual > 0.
//
// Singularity: d along +-k1 (rho < singular_tol) leaves the azimuth undefined
// (the keyhole); the previous azimuth is kept, only theta2 is solved, and the
// solution says so (singular = true). solveRates() then returns dtheta1 = 0.
#pragma once

#include <Eigen/Core>

#include "gimbalsim/dynamics/model.hpp"

namespace gimbalsim::controllers {

using Mat32 = Eigen::Matrix<double, 3, 2>;

/// The gimbal's constant geometry, from a Model (axes normalized).
struct GimbalGeometry {
  Vec3 k1_B = Vec3::UnitZ();         ///< joint 1 axis, base frame (unit)
  Vec3 k2_S1 = Vec3::UnitY();        ///< joint 2 axis, shaft 1 frame (unit)
  Vec3 b_S2 = Vec3::UnitX();         ///< boresight, shaft 2 frame (unit)
  /// Closed form applies: |k1.k2| and |b.k2| below kOrthogonalTol.
  bool closed_form = true;
  Vec3 e1 = Vec3::UnitX(), e2 = Vec3::UnitY(), e3 = Vec3::UnitZ();  ///< closed-form basis, base frame
  double phi0 = 0.0;                 ///< elevation of the boresight at theta2 = 0 [rad]
};
inline constexpr double kOrthogonalTol = 1e-12;  ///< [-] (cosine of the axes' angle)

/// Geometry of the model's gimbal (k1_B, k2_S1, boresight_S2).
GimbalGeometry gimbalGeometry(const Model& m) noexcept;
/// The same from the three vectors (any length > 0): the controller's gimbal.* keys.
GimbalGeometry gimbalGeometry(const Vec3& k1_B, const Vec3& k2_S1, const Vec3& boresight_S2) noexcept;

/// Boresight in the base frame at joint angles theta [rad] (unit vector).
Vec3 boresightB(const GimbalGeometry& g, const Vec2& theta) noexcept;

/// J = d b_B / d theta at theta [1/rad], base frame.
Mat32 boresightJacobian(const GimbalGeometry& g, const Vec2& theta) noexcept;

/// The boresight's curvature along a joint path: d^2 b_B/dt^2 at joint rates
/// dtheta and zero joint accelerations, i.e. (dJ/dt) dtheta [1/s^2], base frame:
///   theta1' k1 x b' + theta2' ((theta1' k1 x R1 k2) x b + R1 k2 x b'),  b' = J dtheta.
/// So b'' = J ddtheta + curvature: what the inverse kinematics' second derivative needs.
Vec3 boresightCurvature(const GimbalGeometry& g, const Vec2& theta, const Vec2& dtheta) noexcept;

struct IkOptions {
  double singular_tol = 1e-6;   ///< rho = |k1 x d| below this: azimuth kept [-]
  int max_iterations = 20;      ///< Gauss-Newton steps (non-orthogonal geometry) [-]
  double step_tol = 1e-14;      ///< Gauss-Newton stops when max |step| is below [rad]
};

struct IkSolution {
  Vec2 theta = Vec2::Zero();  ///< joint angles theta1, theta2 [rad]
  bool singular = false;      ///< d along +-k1: theta1 is the previous azimuth
  bool over_the_top = false;  ///< second branch: cos(theta2 + phi0) < 0 (closed form)
  bool converged = true;      ///< closed form, or Gauss-Newton's last step below step_tol
  int iterations = 0;         ///< Gauss-Newton steps taken (0: closed form)
  double residual = 0.0;      ///< angle between b_B(theta) and d_B [rad]
};

/// Joint angles whose boresight is d_B (base frame, unit or not; zero is not
/// allowed), continuous with theta_prev [rad].
IkSolution solveAngles(const GimbalGeometry& g, const Vec3& d_B, const Vec2& theta_prev,
                       const IkOptions& o = {}) noexcept;

/// Joint rates [rad/s] at theta that move the boresight at d_B_dot (base
/// frame, [1/s]): least squares J dtheta = d_B_dot (normal equations); with
/// k1 x b_B below singular_tol, dtheta1 = 0 and theta2 alone fits.
Vec2 solveRates(const GimbalGeometry& g, const Vec2& theta, const Vec3& d_B_dot,
                const IkOptions& o = {}) noexcept;

/// Joint accelerations [rad/s^2] at theta, dtheta that give the boresight the
/// acceleration d_B_ddot (base frame, [1/s^2]): least squares
/// J ddtheta = d_B_ddot - boresightCurvature(theta, dtheta); keyhole as solveRates.
Vec2 solveAccelerations(const GimbalGeometry& g, const Vec2& theta, const Vec2& dtheta, const Vec3& d_B_ddot,
                        const IkOptions& o = {}) noexcept;

/// A line of sight and its rate in the base frame.
struct LosInBase {
  Vec3 d_B = Vec3::UnitX();       ///< direction, base frame (unit if d_W is)
  Vec3 d_B_dot = Vec3::Zero();    ///< its time derivative seen in the base frame [1/s]
  Vec3 d_B_ddot = Vec3::Zero();   ///< its second derivative seen in the base frame [1/s^2] (losInBaseAcceleration)
};

/// An inertial target direction d_W (unit) and its inertial rate dd_W [1/s],
/// seen from the base at attitude R_WB (base -> inertial, estimated) turning
/// at omega_B (base frame, measured) [rad/s]:
///   d_B = R_WB^T d_W,   d_B_dot = R_WB^T dd_W - omega_B x d_B
/// (d/dt R_WB^T = -[omega_B]x R_WB^T): the second term is the feed-forward of
/// the base's rotation.
LosInBase losInBase(const Vec3& d_W, const Vec3& dd_W, const Mat3& R_WB, const Vec3& omega_B) noexcept;

/// The same with the second derivative: the target's inertial acceleration
/// ddd_W [1/s^2] and the base's angular acceleration alpha_B (base frame) [rad/s^2]:
///   d_B_ddot = R^T ddd_W - omega_B x (R^T dd_W) - alpha_B x d_B - omega_B x d_B_dot
/// (the derivative of d_B_dot; the alpha_B term is the feed-forward of the
/// base's angular acceleration, the reaction the gimbal's own motion induces).
LosInBase losInBase(const Vec3& d_W, const Vec3& dd_W, const Vec3& ddd_W, const Mat3& R_WB, const Vec3& omega_B,
                    const Vec3& alpha_B) noexcept;

}  // namespace gimbalsim::controllers
