// Attitude estimator of the base: a multiplicative complementary filter
// (Mahony, Hamel & Pflimlin, IEEE TAC 2008, in its discrete, star-tracker
// form). A building block of the inertial pointing controller (inertial_reference.cpp
// runs it every period). Pure, allocation-free, noexcept; the state is a small
// copyable struct with a fixed-size ring, the parameters a const struct.
//
// Why this filter and not a multiplicative EKF: two gains (k_p, k_i) with a
// plain meaning (correction bandwidth, bias bandwidth) instead of process and
// measurement covariances to tune; no covariance to propagate, keep positive
// definite or reset; deterministic and allocation-free by construction. An
// MEKF is the upgrade once the gyro's and star tracker's noise models (ARW,
// bias instability, per-axis star-tracker noise) are trusted: it weighs the
// two by those models and reports its own uncertainty.
//
// Conventions. Quaternions are w x y z (Eigen's Quaterniond), base -> inertial
// like gimbal_truth_t.base_quaternion: v_W = R(q_WB) v_B. omega_B, the gyro
// and the bias are base-frame rates [rad/s]; e_B is a base-frame rotation
// vector [rad], eps_W an inertial-frame one. Exp(v) is the unit quaternion of
// rotation vector v, Log its inverse.
//
// Equations, per control period (propagate, gyro rate held over [t_prev, t]):
//   omega_B = gyro_B - bias_B
//   q_WB   <- q_WB (x) Exp(omega_B (t - t_prev))
// and, when a star-tracker sample q_meas stamped t_s <= t arrives (possibly
// late: the estimate at t_s comes from a ring of past estimates, slerp
// between the two around t_s):
//   e_B    = Log(q_hat(t_s)^-1 (x) q_meas)            error, base frame at t_s
//   eps_W  = R(q_hat(t_s)) e_B                        the same, inertial frame
//   dt_s   = min(t_s - t_s,prev, max_gain_interval)   time since the last sample
//   q_WB   <- Exp(min(1, k_p dt_s) eps_W) (x) q_WB      (and every ring entry)
//   bias_B <- clamp(bias_B - k_i dt_s e_B, +-max_bias)
// i.e. Mahony's continuous law omega = gyro - bias + k_p e, d(bias)/dt =
// -k_i e with e held over the sample interval. The correction is made in the
// inertial frame, where a gyro-propagated error does not move, so a late
// sample corrects the current attitude exactly as an on-time one would; it is
// also applied to the ring so the next sample is not corrected twice. The
// first sample initializes (gain 1, bias untouched). During an outage no
// sample comes and the estimate coasts on the gyro: its error grows by the
// integrated (gyro - bias - true rate) only. Small-signal: the loop's
// attitude error poles are the roots of s^2 + k_p s + k_i.
#pragma once

#include <array>
#include <cstdint>

#include "gimbalsim/dynamics/spatial.hpp"

namespace gimbalsim::controllers {

/// Most ring entries a state can hold (history_length <= this).
inline constexpr int kAttitudeHistoryCapacity = 256;

struct AttitudeEstimatorParams {
  double k_p = 0.5;                 ///< attitude correction gain [1/s]
  double k_i = 0.04;                ///< bias integral gain [1/s^2]
  double max_gain_interval = 1.0;   ///< cap on dt_s, the interval a sample's gains scale with [s]
  double max_bias = 0.01;           ///< bias estimate clamp, per axis [rad/s]
  int history_length = 64;          ///< ring entries used, 2 .. kAttitudeHistoryCapacity [-]
  double history_interval = 5e-3;   ///< least spacing of ring entries [s] (64 x 5 ms = 0.32 s of latency)
  double future_tol = 1e-9;         ///< a sample stamped up to this after now counts as now [s]
};

/// A past estimate.
struct AttitudeHistoryEntry {
  double t = 0.0;                   ///< [s]
  Quat q_WB = Quat::Identity();     ///< base -> inertial
};

/// The estimator's memory; copyable, reset by assignment. Do not change
/// history_length of the parameters while a state is in use.
struct AttitudeEstimatorState {
  double t = 0.0;                     ///< time of the estimate [s]
  Quat q_WB = Quat::Identity();       ///< attitude estimate, base -> inertial
  Vec3 bias_B = Vec3::Zero();         ///< gyro bias estimate, base frame [rad/s]
  Vec3 omega_B = Vec3::Zero();        ///< bias-corrected rate of the last period, base frame [rad/s]
  bool initialized = false;           ///< a star-tracker sample has set the attitude
  double t_last_sample = 0.0;         ///< stamp of the last sample used [s]
  long long samples_used = 0;         ///< [-]
  long long samples_rejected = 0;     ///< [-]
  std::array<AttitudeHistoryEntry, kAttitudeHistoryCapacity> ring{};
  int head = 0;                       ///< next ring slot to write
  int count = 0;                      ///< ring entries held
};

/// What became of a star-tracker sample.
enum class SampleStatus : std::uint8_t {
  Initialized,  ///< the first sample: the attitude is set to it
  Corrected,    ///< used
  TooOld,       ///< stamped before the oldest ring entry: dropped
  Future,       ///< stamped after now (+ future_tol): dropped
  OutOfOrder,   ///< stamped at or before the last sample used: dropped
};
const char* describe(SampleStatus s) noexcept;

/// [s] The latency at or beyond which every star-tracker sample is stamped
/// before the ring's oldest entry (TooOld) on a tick grid of control_period
/// [s]: history_length entries, each history_interval apart rounded up to
/// whole periods.
double historySpan(const AttitudeEstimatorParams& p, double control_period) noexcept;

/// Advances the estimate from state.t to t [s] on the gyro rate gyro_B (base
/// frame, bias included, held over the interval) [rad/s]; t <= state.t only
/// updates omega_B. Records the estimate in the ring every history_interval.
void propagate(const AttitudeEstimatorParams& p, AttitudeEstimatorState& s, double t,
               const Vec3& gyro_B) noexcept;

/// Uses a star-tracker attitude q_WB_meas (base -> inertial) stamped t_s [s]
/// (t_s <= s.t: a late sample is compared with the estimate at t_s).
SampleStatus correct(const AttitudeEstimatorParams& p, AttitudeEstimatorState& s, double t_s,
                     const Quat& q_WB_meas) noexcept;

/// Unit quaternion of the rotation vector v [rad] (any frame: the quaternion
/// rotates about v in it).
Quat expRotation(const Vec3& v) noexcept;

/// Rotation vector [rad] of a unit quaternion, angle in [0, pi].
Vec3 logRotation(const Quat& q) noexcept;

}  // namespace gimbalsim::controllers
