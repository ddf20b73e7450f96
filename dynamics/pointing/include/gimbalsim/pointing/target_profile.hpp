// Target profile: where the antenna should point at time t, as desired joint
// angles azimuth (theta1) and elevation (theta2) with their first and second
// derivatives. Angles are those of the line of sight in the inertial frame,
// which is the base frame at t = 0: the base rotates in reaction to the
// gimbal, the encoders cannot see it, and only the truth channel (boresight
// vs losBoresight of the target) reveals it. No LCM, no allocation.
//
// Library gimbalsim_pointing (links gimbalsim_dynamics only): shared by the
// plant side (firmware_sim's truth) and the controller side, so the plant
// never depends on the controller.
#pragma once

#include <cmath>
#include <cstdint>

#include "gimbalsim/dynamics/model.hpp"

namespace gimbalsim::pointing {

/// Which part of the profile a time falls in.
enum class Segment : std::uint8_t {
  Wait,   ///< before slew_start: hold the start angles
  Slew,   ///< minimum-jerk move from start to slew_target over slew_time
  Hold,   ///< hold slew_target for hold_time
  Track,  ///< follow the moving target, for ever
};
const char* describe(Segment s);

/// Desired joint angles and derivatives; index 0 azimuth (theta1), 1 elevation (theta2).
struct ProfileSample {
  Vec2 q = Vec2::Zero();    ///< [rad]
  Vec2 dq = Vec2::Zero();   ///< [rad/s]
  Vec2 ddq = Vec2::Zero();  ///< [rad/s^2]
  Segment segment = Segment::Wait;
};

/// Constant parameters of the profile (config keys `profile.*`; the loader
/// lives with the key registry, not here).
///
/// Slew: minimum-jerk quintic s(u) = 10u^3 - 15u^4 + 6u^5, u = (t - t0)/T:
/// position, rate and acceleration are continuous at both ends; peak rate
/// 1.875 d/T, peak acceleration 5.774 d/T^2 for a move of d [rad].
///
/// Track (tau = time since the track began), per axis:
///   q(tau) = q_hold + r (tau - T_r (1 - exp(-tau/T_r))) + A (1 - cos(2 pi tau / P))
/// a pass across the sky at rate r (like a relay satellite's line of sight
/// drifting), ramped in with time constant T_r so the rate starts from 0,
/// plus a nutation of amplitude A and period P that also starts at rate 0.
/// Position and rate are continuous at tau = 0; |dq| <= |r| + 2 pi A / P and
/// |ddq| <= |r|/T_r + A (2 pi / P)^2.
struct TargetProfile {
  Vec2 start{0.0, 0.0};             ///< angles before the slew [rad]
  double slew_start = 0.0;          ///< [s]
  Vec2 slew_target{0.5, 0.3};       ///< angles at the end of the slew [rad]
  double slew_time = 2.0;           ///< [s], > 0
  double hold_time = 1.0;           ///< [s], >= 0
  Vec2 track_rate{0.02, -0.01};     ///< asymptotic pass rate r [rad/s]
  double track_ramp_time = 1.0;     ///< T_r [s], > 0
  Vec2 track_amplitude{0.01, 0.005};  ///< nutation amplitude A [rad]
  Vec2 track_period{8.0, 5.0};      ///< nutation period P [s], > 0

  double slewEnd() const noexcept { return slew_start + slew_time; }
  double trackStart() const noexcept { return slewEnd() + hold_time; }

  /// Desired angles at time t [s] (simulation time, t = 0 at the start).
  ProfileSample at(double t) const noexcept;
};

/// Boresight unit vector (inertial) the gimbal produces at theta1 = az,
/// theta2 = el with the base at its initial pose (all frames parallel at
/// q = 0, so R = Rot(k1_B, az) Rot(k2_S1, el)); joint-2 clearance displaces
/// the journal but does not rotate it, so it plays no part.
Vec3 losBoresight(const Model& m, double az, double el) noexcept;

/// The same for any two-axis geometry: joint 1 axis k1_B (base frame), joint
/// 2 axis k2_S1 (shaft 1 frame), boresight b_S2 (shaft 2 frame), all frames
/// parallel at zero angles; the boresight in the base frame, unit. The one
/// formula the plant's truth and the controller's inverse kinematics share.
Vec3 gimbalBoresight(const Vec3& k1_B, const Vec3& k2_S1, const Vec3& b_S2, double az, double el) noexcept;

/// Angle between two directions [rad]: atan2(|a x b|, a.b), exact near 0
/// (acos loses half the digits there). Neither needs to be unit. The one
/// angle-between-directions function of the tree: tests and tools call it.
inline double pointingError(const Vec3& a, const Vec3& b) noexcept {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace gimbalsim::pointing
