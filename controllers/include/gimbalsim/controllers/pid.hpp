// Per-axis PID with feed-forward, anti-windup and torque limits: the pointing
// controller's law. Model/State split as in the dynamics: a const
// ControllerConfig, a small copyable ControllerState, and
//   ControlOutput update(const ControllerConfig&, ControllerState&, const Measurement&) noexcept
// called once per control period on what real firmware reports (quantized
// encoder angles, rates from status). No LCM, no allocation, no exception.
//
// Law, per axis i (e = q_ref - q_meas, all from the profile at the measurement time):
//   tau_u = J_i ddq_ref + kp e + kd (dq_ref - w) + I
//   tau   = clamp(tau_u, -limit, +limit)
// (with approach_margin > 0, large errors use kd (dq_ref + sign(e) sqrt(2 a |e|) - w)
// instead of the PD pair where that asks for less: see pid.cpp).
// J_i ddq_ref is the acceleration feed-forward (inertia estimate J_i); kd dq_ref
// is the rate feed-forward and -kd w the derivative on measurement (no kick
// when the reference jumps). w is the status rate, or the backward difference
// of the encoder angle (over the samples' real spacing) through a first-order
// low-pass filter.
// The integral I (kept in torque units, so a gain change does not bump it):
//   none:             I += Ts ki e
//   clamping:         as none, but not while saturated and e pushes further into it
//   back_calculation: I += Ts (ki e + k_aw (tau - tau_u))  (Astrom & Hagglund, 2006)
// and, with clamping or back-calculation, |I| <= limit (none: unbounded, the
// naive law, kept to show what windup does).
#pragma once

#include <array>
#include <cstdint>

#include "gimbalsim/pointing/target_profile.hpp"

namespace gimbalsim::controllers {

// The target profile lives in the pointing library (shared with the plant
// side); the controller uses it under its own names.
using pointing::ProfileSample;
using pointing::Segment;
using pointing::TargetProfile;

enum class AntiWindup : std::uint8_t { None, Clamping, BackCalculation };
enum class RateSource : std::uint8_t { Status, Difference };

/// Gains and limits of one axis (config keys `azimuth.*`, `elevation.*`).
struct AxisGains {
  double kp = 0.0;            ///< proportional [N m/rad]
  double ki = 0.0;            ///< integral [N m/(rad s)]
  double kd = 0.0;            ///< derivative [N m s/rad]
  double inertia = 0.0;       ///< acceleration feed-forward inertia estimate J [kg m^2]
  double torque_limit = 50.0; ///< command limit [N m], > 0
  double aw_gain = 0.0;       ///< back-calculation gain k_aw = 1/T_t [1/s]
};

/// Constant configuration of the controller (the controller's "Model").
struct ControllerConfig {
  std::array<AxisGains, 2> axis{};   ///< 0 azimuth (theta1), 1 elevation (theta2)
  double period = 1.0e-3;            ///< control period Ts [s]
  AntiWindup anti_windup = AntiWindup::BackCalculation;
  RateSource rate_source = RateSource::Status;
  double rate_filter_hz = 100.0;     ///< low-pass cutoff of the differenced rate [Hz]
  /// Large-error approach: closing rate capped at sqrt(2 a |e|), a = margin *
  /// torque_limit / inertia (needs inertia > 0 and kd > 0); 0 = plain PD [-]
  double approach_margin = 0.0;
  TargetProfile profile;
};

/// What the controller sees each period.
struct Measurement {
  double t = 0.0;             ///< time of the sample [s] (profile time)
  Vec2 theta = Vec2::Zero();  ///< encoder angles theta1, theta2 [rad] (quantized)
  Vec2 dtheta = Vec2::Zero(); ///< reported rates [rad/s] (used when rate_source = status)
};

/// Memory between calls (the controller's "State"); copyable, reset by assignment.
struct ControllerState {
  Vec2 integral = Vec2::Zero();    ///< integral term I [N m]
  Vec2 theta_prev = Vec2::Zero();  ///< last encoder angles [rad]
  double t_prev = 0.0;             ///< time of theta_prev [s]
  Vec2 rate = Vec2::Zero();        ///< filtered rate estimate [rad/s]
  bool primed = false;             ///< theta_prev holds a sample
};

/// One update's result; tau is the command.
struct ControlOutput {
  Vec2 tau = Vec2::Zero();         ///< commanded torque, limited [N m]
  Vec2 tau_unsat = Vec2::Zero();   ///< before the limit [N m]
  Vec2 error = Vec2::Zero();       ///< q_ref - theta [rad]
  Vec2 rate = Vec2::Zero();        ///< rate used in the derivative term [rad/s]
  ProfileSample ref;               ///< the reference at the measurement time
  std::array<bool, 2> saturated{}; ///< |tau_unsat| > limit
};

ControlOutput update(const ControllerConfig& c, ControllerState& s, const Measurement& meas) noexcept;

/// Gains placing the closed-loop poles of J s^3 + kd s^2 + kp s + ki at a
/// triple pole -omega (kd = 3 J w, kp = 3 J w^2, ki = J w^3); inertia = J.
AxisGains triplePoleGains(double J, double omega, double torque_limit, double aw_gain);

}  // namespace gimbalsim::controllers
