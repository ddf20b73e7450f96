#include "gimbalsim/dynamics/model.hpp"

#include <cmath>

#include "gimbalsim/dynamics/contact_law.hpp"

namespace gimbalsim {

namespace {

/// A unit vector normal to k: the part of ref normal to k, or of another
/// base axis when ref is (nearly) parallel to k.
Vec3 normalTo(const Vec3& k, const Vec3& ref) {
  Vec3 u = ref - ref.dot(k) * k;
  if (u.norm() < 1e-9) {
    u = std::fabs(k.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    u -= u.dot(k) * k;
  }
  return u.normalized();
}

/// Appends joint j's group to the chain from index i: ideal [R(k)]; planar
/// [P(u1), P(u2), R(k)]; spatial [P(u1), P(u2), R(u1), R(u2), R(k)] (tilt
/// hinges about the current axes, Rot(x) Rot(y) Rot(z)). The virtual bodies
/// are massless; the last one carries the child's inertia.
int appendGroup(Model& m, int i, ClearanceKind kind, const Vec3& origin, const Vec3& k, const Vec3& u1,
                const Vec3& u2, const SpatialInertia& child) {
  using R = JointKind;
  const auto add = [&](JointKind kd, const Vec3& axis, const Vec3& o) {
    m.chain[i] = {kd, axis, o};
    m.I_chain[i] = SpatialInertia{};
    ++i;
  };
  if (kind == ClearanceKind::Ideal) {
    add(R::Revolute, k, origin);
  } else {
    add(R::Prismatic, u1, origin);
    add(R::Prismatic, u2, Vec3::Zero());
    if (kind == ClearanceKind::Spatial) {
      add(R::Revolute, u1, Vec3::Zero());
      add(R::Revolute, u2, Vec3::Zero());
    }
    add(R::Revolute, k, Vec3::Zero());
  }
  m.I_chain[i - 1] = child;
  return i;
}

}  // namespace


double Model::hertzStiffness(const ContactParams& c, RadiusMode mode) {
  // Paper eq. 11: K = 4 sqrt(R) / (3 pi (h_i + h_j)), h_k = (1 - nu_k^2) / (pi E_k).
  const double Ri = c.bearing_radius, Rj = c.journal_radius;
  const double R = mode == RadiusMode::Paper ? Ri * Rj / (Ri + Rj)   // convex-convex (paper)
                                             : Ri * Rj / (Ri - Rj);  // conformal (Flores & Ambrosio 2004)
  const double hi = (1.0 - c.nu_bearing * c.nu_bearing) / (M_PI * c.E_bearing);
  const double hj = (1.0 - c.nu_journal * c.nu_journal) / (M_PI * c.E_journal);
  return 4.0 * std::sqrt(R) / (3.0 * M_PI * (hi + hj));
}

void deriveBearing(ContactParams& c) {
  c.clearance = c.bearing_radius - c.journal_radius;
  c.K = c.stiffness_scale * Model::hertzStiffness(c, c.radius_mode);
  c.chi = dampingFactor(c.damping, c.restitution);
}

void setClearance(ContactParams& b, double c) {
  b.journal_radius = b.bearing_radius - c;
  deriveBearing(b);
  b.clearance = c;  // as asked, not R_i - R_j rounded
}

void Model::finalize() {
  for (ContactParams& c : bearing) deriveBearing(c);

  k1_B.normalize();
  k2_S1.normalize();
  boresight_S2.normalize();
  // Joint-plane bases: joint 2's u1 along the part of shaft 1's
  // joint-1-to-joint-2 direction normal to k2; joint 1's along base x.
  u1_S1 = normalTo(k2_S1, r_J2_S1_S1);
  u2_S1 = k2_S1.cross(u1_S1);
  u1_B = normalTo(k1_B, Vec3::UnitX());
  u2_B = k1_B.cross(u1_B);

  I_base = SpatialInertia::fromBody(base.mass, base.com, base.inertia);
  const SpatialInertia I1 = SpatialInertia::fromBody(shaft1.mass, shaft1.com, shaft1.inertia);
  const SpatialInertia I2 = SpatialInertia::fromBody(shaft2.mass, shaft2.com, shaft2.inertia);
  // Clearance joints as chains of massless prismatic and revolute bodies:
  // the system stays a tree and needs no constraint equations.
  chain.fill({});
  I_chain.fill({});
  const int n1 = appendGroup(*this, 0, joint1_kind, r_J1_B_B, k1_B, u1_B, u2_B, I1);
  appendGroup(*this, n1, joint2_kind, r_J2_S1_S1, k2_S1, u1_S1, u2_S1, I2);
}

}  // namespace gimbalsim
