// The antenna's boresight tracker fused with the joint encoders (config key
// antenna.tracker). The tracker reads where the antenna itself points, play
// and tilt included; the encoders read where the motors are. Their
// difference at the tracker's sample time, in joint coordinates, is the
// play's offset o (antenna minus encoder); the law's position error becomes
//   e = q_ref - (theta_enc + o)
// a load-side position loop, while its rate term stays on the motor's rate
// (the light side's damping, play_guard.hpp). Between samples (the tracker's
// rate, latency, outages, dropouts) o is held; the o the law uses moves
// toward the measured one at most antenna.offset_rate, so a first sample or
// the end of an outage does not kick the command (docs/MODEL.md 11.7).
// Fixed-size state, noexcept, no allocation.
#pragma once

#include <array>
#include <cstdint>

#include "gimbalsim/contract/messages.hpp"
#include "gimbalsim/dynamics/spatial.hpp"

namespace gimbalsim::controllers {

/// Configuration (keys antenna.*).
struct TrackerFusionParams {
  bool use_tracker = true;    ///< antenna.tracker: use (when the plant sends it) | ignore
  double offset_rate = 0.05;  ///< [rad/s] most the applied offset moves per second while acquiring, per axis
  double bandwidth = 12.0;    ///< [rad/s] triple pole of the loop at the antenna once a play is seen, on each axis's inertia
  double motor_damping = 20.0;  ///< [N m s/rad] the motor's rate against the antenna's
  double engaged_rate = 1.0e-3; ///< [rad/s] the integral runs only while motor and antenna move within this
  double integral_leak_time = 0.2; ///< [s] otherwise it decays toward 0 with this time constant (0: held)
};

/// Ticks without a sample after which the offset is acquired again (rate-limited).
inline constexpr std::int64_t kRelockTicks = 50;

/// Memory (part of ControllerState).
struct TrackerFusionState {
  static constexpr int kSize = 64;  ///< ticks of history: a tracker latency up to 64 periods
  std::array<std::int64_t, kSize> seq = filled(-1);   ///< tick held in each slot (-1: none)
  std::array<Vec2, kSize> lead{};                     ///< [rad] q_ref - theta_enc at that tick
  std::array<double, kSize> theta2{};                 ///< [rad] encoder elevation at that tick
  bool pending = false;              ///< a delivered reading not yet folded in
  double pending_time = -1.0;        ///< [s] its sample time
  Vec2 pending_reading = Vec2::Zero();  ///< [rad] its (u, v) rotation boresight -> target
  bool measured = false;             ///< offset_measured holds a sample
  Vec2 offset_measured = Vec2::Zero();  ///< [rad] the play's offset at the last sample, joint coordinates
  Vec2 offset = Vec2::Zero();        ///< [rad] the offset the law uses (rate-limited toward offset_measured while acquiring)
  bool locked = false;               ///< offset caught up with offset_measured: it follows each sample
  std::int64_t used_tick = -1;       ///< tick of the last sample folded in
  std::int64_t gyro_seq = -1;        ///< tick of gyro_rate (-1: none)
  Vec3 gyro_rate = Vec3::Zero();     ///< [rad/s] the antenna gyro's rate, antenna frame
  long long used = 0;                ///< readings folded in
  long long rejected = 0;            ///< readings refused: non-finite, implausible, or outside the history

 private:
  static std::array<std::int64_t, kSize> filled(std::int64_t v) {
    std::array<std::int64_t, kSize> a;
    a.fill(v);
    return a;
  }
};

/// Keeps a delivered tracker reading of an antenna message (tracker_valid,
/// no outage) for the next update, and its gyro sample; a non-finite or
/// implausible one is counted and left out.
void noteAntennaReading(TrackerFusionState& s, const contract::Antenna& antenna) noexcept;

/// Whether the loop has heard the antenna's own sensors (a gyro sample or a
/// tracker reading folded in) and uses them (antenna.tracker use).
inline bool antennaHeard(const TrackerFusionParams& p, const TrackerFusionState& s) noexcept {
  return p.use_tracker && (s.gyro_seq >= 0 || s.measured);
}

/// The joint corrections dtheta [rad] whose rotation has the reading's (u, v)
/// components at elevation theta2 (the tracker's axes from the controller's
/// gimbal: k1_B azimuth, base frame; k2_S1 elevation; boresight_S2; unit).
/// Near the keyhole (azimuth's u, v lever below 0.05) the azimuth part is 0.
Vec2 trackerJointError(const Vec3& k1_B, const Vec3& k2_S1, const Vec3& boresight_S2, double theta2,
                       const Vec2& reading) noexcept;

/// The antenna's rate in joint coordinates [rad/s] at tick k from its gyro:
/// the antenna's rate less the base's (omega_B, base frame) on the tracker's
/// u, v axes, mapped as trackerJointError maps a reading. False (rate
/// untouched) without a gyro sample of tick k or with antenna.tracker ignore.
bool loadRate(const TrackerFusionParams& p, const Vec3& k1_B, const Vec3& k2_S1, const Vec3& boresight_S2,
              const TrackerFusionState& s, std::int64_t k, const Vec2& theta, const Vec3& omega_B, Vec2& rate) noexcept;

/// Records tick k's lead (q_ref - theta_enc) and encoder elevation, folds in
/// a pending reading whose tick is in the history and returns the offset the
/// law uses [rad]: it follows the samples once locked; while acquiring (the
/// first sample, or one after more than kRelockTicks without) it moves
/// toward them at most offset_rate * period a tick.
Vec2 loadOffset(const TrackerFusionParams& p, const Vec3& k1_B, const Vec3& k2_S1, const Vec3& boresight_S2,
                TrackerFusionState& s, std::int64_t k, double period, const Vec2& lead, double theta2) noexcept;

}  // namespace gimbalsim::controllers
