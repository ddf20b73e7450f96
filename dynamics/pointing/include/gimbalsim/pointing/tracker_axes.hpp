// What a boresight tracker on the antenna reads, defined once for the plant
// that measures it (firmware_sim/antenna_sensors.hpp) and the controller that
// inverts it (controllers/tracker_fusion.hpp): the rotation eps that takes the
// boresight b onto the target's line of sight d (axis b x d, angle
// atan2(|b x d|, b.d)), in the antenna frame, on its axes u = the elevation
// axis made perpendicular to b and v = b x u. All frames are parallel at zero
// joint angles, so the elevation axis in the antenna frame is k2_S1.
#pragma once

#include "gimbalsim/dynamics/spatial.hpp"
#include "gimbalsim/pointing/target_profile.hpp"

namespace gimbalsim::pointing {

/// The tracker's axes in the antenna (shaft 2) frame, unit: b the boresight, u, v.
struct TrackerAxes {
  Vec3 b = Vec3::UnitX(), u = Vec3::UnitY(), v = Vec3::UnitZ();
};

inline TrackerAxes trackerAxes(const Vec3& k2_S1, const Vec3& boresight_S2) noexcept {
  TrackerAxes a;
  a.b = boresight_S2.normalized();
  Vec3 u = k2_S1 - k2_S1.dot(a.b) * a.b;
  if (u.norm() < 1e-9) u = a.b.unitOrthogonal();  // an elevation axis along the boresight: any perpendicular
  a.u = u.normalized();
  a.v = a.b.cross(a.u);
  return a;
}

/// The rotation vector taking direction `from` onto `to` (both unit): axis
/// from x to, angle pointingError (exact near 0).
inline Vec3 rotationOnto(const Vec3& from, const Vec3& to) noexcept {
  const Vec3 axis = from.cross(to);
  const double n = axis.norm();
  return n > 0.0 ? Vec3(axis * (pointingError(from, to) / n)) : Vec3::Zero();
}

/// The reading without noise or bias of an antenna at R_FA (antenna -> any
/// frame F) whose target's line of sight is target_F (unit, frame F).
inline Vec2 trackerReading(const TrackerAxes& a, const Mat3& R_FA, const Vec3& target_F) noexcept {
  const Vec3 eps_A = R_FA.transpose() * rotationOnto(R_FA * a.b, target_F);
  return {eps_A.dot(a.u), eps_A.dot(a.v)};
}

/// The rotation a reading stands for, in frame F, for an antenna at R_FA.
inline Vec3 trackerRotation(const TrackerAxes& a, const Mat3& R_FA, const Vec2& reading) noexcept {
  return R_FA * (reading(0) * a.u + reading(1) * a.v);
}

}  // namespace gimbalsim::pointing
