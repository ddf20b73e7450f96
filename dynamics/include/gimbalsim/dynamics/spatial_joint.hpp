// Contact of a spatial clearance joint at the bearing's two end planes
// (docs/MODEL.md, spatial clearance): the journal centre p in the bearing's
// mid-plane and the journal axis tilted by alpha, beta, so the journal can
// touch the bearing at either end. Everything here is in the bearing frame B
// (x_B = u1, y_B = u2, z_B = k, origin at the bearing centre), from the
// joint's own five coordinates: pure functions; contact_ends.hpp maps a
// joint's group and the bearing body's motion into them.
#pragma once

#include <array>
#include <cmath>

#include "gimbalsim/dynamics/contact_law.hpp"

namespace gimbalsim {

/// The group of a spatial clearance joint: [p_x, p_y, alpha, beta, theta]
/// ([m], [m], [rad], [rad], [rad]) and their rates.
using SpatialCoords = Eigen::Matrix<double, 5, 1>;

/// One bearing end s = -1 (index 0) or +1 (index 1) at one evaluation.
struct SpatialEnd {
  double e = 0.0;                ///< eccentricity of the journal axis in the end plane [m]
  double delta = 0.0;            ///< penetration e - c [m] (negative: free)
  Vec3 n_B = Vec3::Zero();       ///< unit normal in the end plane (zero when e = 0)
  double vn = 0.0;               ///< V . n, normal relative velocity of the material points [m/s]
  Vec3 vt_B = Vec3::Zero();      ///< tangential relative velocity V - vn n [m/s]
  double fn = 0.0;               ///< normal force, stiffness K / 2 [N]
  Vec3 ft_B = Vec3::Zero();      ///< friction force on the journal [N]
  Vec3 M_B = Vec3::Zero();       ///< where the force pair acts [m]
};

/// Both ends, the tilt, and the generalised force the contact puts on the
/// joint's five coordinates (the pair is internal to the tree above the
/// bearing body, so no other coordinate sees it).
struct SpatialContact {
  std::array<SpatialEnd, 2> end{};
  double gamma = 0.0;                        ///< tilt angle between z_J and z_B [rad]
  SpatialCoords tau = SpatialCoords::Zero();  ///< [N, N, N m, N m, N m]
};

/// Journal axis z_J = Rot(x, alpha) Rot(y, beta) e_z in B.
inline Vec3 journalAxis(double alpha, double beta) {
  return {std::sin(beta), -std::sin(alpha) * std::cos(beta), std::cos(alpha) * std::cos(beta)};
}

/// Hinge axes of alpha, beta, theta in B: x_B, Rot(x, alpha) y_B, z_J.
inline std::array<Vec3, 3> spatialHingeAxes(double alpha, double beta) {
  return {Vec3::UnitX(), Vec3(0.0, std::cos(alpha), std::sin(alpha)), journalAxis(alpha, beta)};
}

/// Where the journal axis meets the end plane z_B = z_end: A = p + (z_end /
/// z_J . z_B) z_J, in B [m]. Its x, y are the end's eccentricity vector.
inline Vec3 spatialEndPoint(const Vec3& p, const Vec3& zJ, double z_end) { return p + (z_end / zJ.z()) * zJ; }

/// Penetration delta_s = |A_s| - c [m] of end s (-1 or +1) and its time
/// derivative [m/s] (geometric, for locating the switch; the contact law uses
/// the material points' v_n instead, docs/MODEL.md section 2.7).
inline void spatialEndGap(double clearance, double L, double s, const SpatialCoords& q, const SpatialCoords& v,
                          double& delta, double& rate) {
  const double z_end = 0.5 * s * L;
  const Vec3 A = spatialEndPoint(Vec3(q(0), q(1), 0.0), journalAxis(q(2), q(3)), z_end);
  const double e = std::hypot(A.x(), A.y());
  delta = e - clearance;
  // A = p + z_end (tan(beta) / cos(alpha), -tan(alpha), 1), differentiated.
  const double ca = std::cos(q(2)), ta = std::tan(q(2)), cb = std::cos(q(3)), tb = std::tan(q(3));
  const double dx = v(0) + z_end * (v(3) / (cb * cb * ca) + v(2) * tb * ta / ca);
  const double dy = v(1) - z_end * v(2) / (ca * ca);
  rate = e > 0.0 ? (A.x() * dx + A.y() * dy) / e : 0.0;
}

/// Generalised force on the five coordinates of the motor couple tau z_J on
/// the journal (and -tau z_J on the bearing): tau times the hinge axes' z_J
/// components, so alpha gets tau sin(beta) and beta nothing [N m].
inline SpatialCoords spatialCoupleForce(double tau, double alpha, double beta) {
  const std::array<Vec3, 3> a = spatialHingeAxes(alpha, beta);
  const Vec3 zJ = a[2];
  SpatialCoords g;
  g << 0.0, 0.0, tau * a[0].dot(zJ), tau * a[1].dot(zJ), tau;
  return g;
}

/// Contact at both bearing ends. q, v: the group's coordinates and rates;
/// omegaP_B: the bearing body's angular velocity in B [rad/s]; L: bearing
/// length [m]; v0: each end's impact velocity [m/s] (K / 2 and its own v0 per
/// end). Friction in the tangent plane: -mu c_d F_n v_t / |v_t|.
inline void spatialContact(const ContactParams& cp, double L, const SpatialCoords& q, const SpatialCoords& v,
                           const Vec3& omegaP_B, const std::array<double, 2>& v0, SpatialContact& out) {
  const Vec3 p(q(0), q(1), 0.0), pd(v(0), v(1), 0.0);
  const std::array<Vec3, 3> a = spatialHingeAxes(q(2), q(3));
  const Vec3& zJ = a[2];
  // Journal angular velocity relative to the bearing body.
  const Vec3 w_rel = v(2) * a[0] + v(3) * a[1] + v(4) * a[2];
  out.gamma = std::atan2(zJ.cross(Vec3::UnitZ()).norm(), zJ.z());
  out.tau.setZero();
  for (int i = 0; i < 2; ++i) {
    const double s = i == 0 ? -1.0 : 1.0;
    SpatialEnd& c = out.end[i];
    const double z_end = 0.5 * s * L;
    const Vec3 A = spatialEndPoint(p, zJ, z_end);
    c.e = std::hypot(A.x(), A.y());
    c.delta = c.e - cp.clearance;
    c.n_B = c.e > 0.0 ? Vec3(A.x() / c.e, A.y() / c.e, 0.0) : Vec3::Zero();
    const Vec3 QB = Vec3(0.0, 0.0, z_end) + cp.bearing_radius * c.n_B;
    const Vec3 QJ = A + cp.journal_radius * c.n_B;
    c.M_B = 0.5 * (QB + QJ);
    // Material points: the journal's at Q_J minus the bearing's at Q_B; the
    // bearing body's own motion adds omega_P x (Q_J - Q_B).
    const Vec3 V = pd + w_rel.cross(QJ - p) + omegaP_B.cross(QJ - QB);
    c.vn = V.dot(c.n_B);
    c.vt_B = V - c.vn * c.n_B;
    c.fn = c.e > 0.0 ? 0.5 * normalForce(cp, c.delta, c.vn, v0[i]) : 0.0;
    const double vt = c.vt_B.norm();
    c.ft_B.setZero();
    if (vt > 0.0) c.ft_B = (frictionForce(cp, c.fn, vt) / vt) * c.vt_B;
    if (c.fn == 0.0 && c.ft_B.isZero(0.0)) continue;
    const Vec3 F = -c.fn * c.n_B + c.ft_B;  // on the journal, at M
    const Vec3 r = c.M_B - p;               // from the hinges' common point
    out.tau(0) += F.x();
    out.tau(1) += F.y();
    for (int h = 0; h < 3; ++h) out.tau(2 + h) += a[h].dot(r.cross(F));
  }
}

}  // namespace gimbalsim
