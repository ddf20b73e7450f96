#include "gimbalsim/dynamics/model.hpp"

#include <cmath>

#include "gimbalsim/dynamics/contact_law.hpp"

namespace gimbalsim {

double Model::hertzStiffness(const ContactParams& c, RadiusMode mode) {
  // Paper eq. 11: K = 4 sqrt(R) / (3 pi (h_i + h_j)), h_k = (1 - nu_k^2) / (pi E_k).
  const double Ri = c.bearing_radius, Rj = c.journal_radius;
  const double R = mode == RadiusMode::Paper ? Ri * Rj / (Ri + Rj)   // convex-convex (paper)
                                             : Ri * Rj / (Ri - Rj);  // conformal (Flores & Ambrosio 2004)
  const double hi = (1.0 - c.nu_bearing * c.nu_bearing) / (M_PI * c.E_bearing);
  const double hj = (1.0 - c.nu_journal * c.nu_journal) / (M_PI * c.E_journal);
  return 4.0 * std::sqrt(R) / (3.0 * M_PI * (hi + hj));
}

void Model::finalize() {
  ContactParams& c = contact;
  c.clearance = c.bearing_radius - c.journal_radius;
  c.K = c.stiffness_scale * hertzStiffness(c, c.radius_mode);
  c.chi = dampingFactor(c.damping, c.restitution);

  k1_B.normalize();
  k2_S1.normalize();
  boresight_S2.normalize();
  // Joint-plane basis: u1 along the part of shaft 1's joint-1-to-joint-2
  // direction normal to k2 (or any normal if they are parallel), u2 = k2 x u1.
  Vec3 ref = r_J2_S1_S1 - r_J2_S1_S1.dot(k2_S1) * k2_S1;
  if (ref.norm() < 1e-9) {
    ref = std::fabs(k2_S1.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    ref -= ref.dot(k2_S1) * k2_S1;
  }
  u1_S1 = ref.normalized();
  u2_S1 = k2_S1.cross(u1_S1);

  I_base = SpatialInertia::fromBody(base.mass, base.com, base.inertia);
  const SpatialInertia I1 = SpatialInertia::fromBody(shaft1.mass, shaft1.com, shaft1.inertia);
  const SpatialInertia I2 = SpatialInertia::fromBody(shaft2.mass, shaft2.com, shaft2.inertia);
  chain[0] = {JointKind::Revolute, k1_B, r_J1_B_B};
  I_chain[0] = I1;
  if (!clearance_joint) {
    chain[1] = {JointKind::Revolute, k2_S1, r_J2_S1_S1};
    I_chain[1] = I2;
  } else {
    // Planar clearance joint as a massless prismatic-prismatic-revolute chain:
    // the system stays a tree and needs no constraint equations.
    chain[1] = {JointKind::Prismatic, u1_S1, r_J2_S1_S1};
    chain[2] = {JointKind::Prismatic, u2_S1, Vec3::Zero()};
    chain[3] = {JointKind::Revolute, k2_S1, Vec3::Zero()};
    I_chain[1] = SpatialInertia{};
    I_chain[2] = SpatialInertia{};
    I_chain[3] = I2;
  }
}

}  // namespace gimbalsim
