// The pointing controller's joint law, per axis: feed-forward, PD on the
// measured rate, an integral with anti-windup, torque limits (docs/bench.md
// "The law"). A const ControllerConfig, a small copyable ControllerState and
// update() once per period; no LCM, no allocation, no exception.
#pragma once

#include <array>
#include <cstdint>

#include "gimbalsim/controllers/attitude_estimator.hpp"
#include "gimbalsim/controllers/fault_monitor.hpp"
#include "gimbalsim/controllers/model_feedforward.hpp"
#include "gimbalsim/controllers/play_guard.hpp"
#include "gimbalsim/controllers/tracker_fusion.hpp"
#include "gimbalsim/input/input_error.hpp"
#include "gimbalsim/pointing/target_profile.hpp"

namespace gimbalsim::controllers {

// The target profile lives in the pointing library (shared with the plant
// side); the controller uses it under its own names.
using pointing::ProfileSample;
using pointing::Segment;
using pointing::TargetProfile;

enum class AntiWindup : std::uint8_t { None, Clamping, BackCalculation };
enum class RateSource : std::uint8_t { Status, Difference };
/// What the joint law tracks: inertial pointing (IK through the estimated attitude) or the profile's joint angles.
enum class PointingMode : std::uint8_t { Inertial, Joint };
/// The inertial target: the profile's (az, el) turned into a direction at the initial base pose, or a fixed one.
enum class PointingTarget : std::uint8_t { Profile, Fixed };
/// What the acceleration feed-forward J_i a_i takes for a_i (inertial mode): the profile's joint
/// acceleration, or each shaft's inertial angular acceleration about its joint from the IK's second
/// derivative (curvature, base rate and the base's angular acceleration, the reaction included).
/// Model: the computed torque of the free-floating plant's rigid-body model (model_feedforward.hpp).
enum class AccelFeedForward : std::uint8_t { Profile, Inertial, Model };

/// The gimbal geometry the controller assumes (keys gimbal.*; the paper's z, y, x).
struct GimbalAxes {
  Vec3 joint1_axis = Vec3::UnitZ();  ///< azimuth axis, base frame
  Vec3 joint2_axis = Vec3::UnitY();  ///< elevation axis, shaft 1 frame
  Vec3 boresight = Vec3::UnitX();    ///< boresight, shaft 2 frame
  /// The azimuth inertia's elevation dependence C [kg m^2]: J1(theta2) =
  /// azimuth.inertia + C (cos 2 theta2 - 1), with its velocity-product
  /// feed-forward (0: constant J1, the old law; controllers/config/default.yaml says why).
  double azimuth_inertia_cos2 = 8.205;
};

/// Gains and limits of one axis (config keys `azimuth.*`, `elevation.*`).
struct AxisGains {
  double kp = 0.0;            ///< proportional [N m/rad]
  double ki = 0.0;            ///< integral [N m/(rad s)]
  double kd = 0.0;            ///< derivative [N m s/rad]
  double inertia = 0.0;       ///< acceleration feed-forward inertia estimate J [kg m^2]
  double torque_limit = 50.0; ///< command limit [N m], > 0
  double aw_gain = 0.0;       ///< back-calculation gain k_aw = 1/T_t [1/s]
  /// Inertia on the motor's side of a play in this axis's drive [kg m^2] (play_guard.hpp); 0: no guard
  double play_inertia = 0.0;
};

/// Constant configuration of the controller (the controller's "Model").
/// Its defaults ARE the default controller: controllers/config/default.yaml
/// states the same values with their derivation (a test compares every key),
/// and a program given no file runs these.
struct ControllerConfig {
  /// 0 azimuth (theta1), 1 elevation (theta2): triple pole at -20 rad/s (default.yaml says why).
  std::array<AxisGains, 2> axis{AxisGains{.kp = 21120.0, .ki = 140800.0, .kd = 1056.0, .inertia = 17.01,
                                          .torque_limit = 50.0, .aw_gain = 20.0, .play_inertia = 0.1},
                                AxisGains{.kp = 21000.0, .ki = 140000.0, .kd = 1050.0, .inertia = 16.91,
                                          .torque_limit = 50.0, .aw_gain = 20.0, .play_inertia = 0.5}};
  double period = 1.0e-3;            ///< control period Ts [s]
  AntiWindup anti_windup = AntiWindup::BackCalculation;
  RateSource rate_source = RateSource::Status;
  double rate_filter_hz = 100.0;     ///< low-pass cutoff of the differenced rate [Hz]
  /// Large-error approach: closing rate capped at sqrt(2 a |e|), a = margin *
  /// torque_limit / inertia (needs inertia > 0 and kd > 0); 0 = plain PD [-]
  double approach_margin = 0.5;
  TargetProfile profile = [] {
    TargetProfile p;
    p.slew_start = 0.5;  // [s] a still start before the slew
    return p;
  }();
  PointingMode pointing_mode = PointingMode::Inertial;
  PointingTarget target = PointingTarget::Profile;
  Vec3 fixed_direction = Vec3::UnitX();  ///< inertial target direction with target = fixed (any length > 0)
  AccelFeedForward accel_feedforward = AccelFeedForward::Model;
  double base_accel_filter_hz = 50.0;    ///< low-pass cutoff of the differenced base rate (alpha_B) [Hz]
  /// How far ahead the feed-forward torque is extrapolated (its backward
  /// difference): a command acts from the next tick on, over one period [s]
  double feedforward_lead = 1.5e-3;
  GimbalAxes gimbal;
  PlantMass plant = paperPlantMass();    ///< mass properties for accel_feedforward = model (keys plant.*)
  /// Derived from plant and gimbal at load (finalizePlant, config.hpp): the model the feed-forward runs.
  Model plant_model = plantModel(paperPlantMass(), Vec3::UnitZ(), Vec3::UnitY(), Vec3::UnitX());
  AttitudeEstimatorParams estimator;     ///< k_p, k_i are keys; the rest its defaults
  MonitorConfig monitor;                 ///< what counts as a stale status or a suspect encoder (fault_monitor.hpp)
  TrackerFusionParams antenna;           ///< the antenna tracker in the position loop (tracker_fusion.hpp)
  /// Set at load (config.cpp): where a value that runs as another (key_use.hpp controllerValueRunsAsAnother) was
  /// given, as the loader names a place (file:line:column, or the override); empty text when none. (pass 104,
  /// 106, 107) its refusals said "the controller configuration", naming neither the file nor the line.
  Problem runs_as_another;
};

/// The base attitude sensors of the same tick (contract::Attitude, as the controller uses it).
struct AttitudeMeasurement {
  bool gyro_valid = true;          ///< false: no gyro sample this period (the previous rate is held)
  Vec3 gyro = Vec3::Zero();        ///< rate gyro, base frame, bias included [rad/s]
  bool star_valid = false;         ///< a new star tracker sample this period
  double star_time = -1.0;         ///< its sample time t_s [s]
  Quat star_q = Quat::Identity();  ///< its attitude, base -> inertial
  bool star_outage = false;        ///< the star tracker reports an outage
};

/// The attitude messages of the last kSize ticks by seq, so that a late
/// status (fault_monitor.hpp) is paired with the gyro sample of its own tick.
struct AttitudeHistory {
  static constexpr int kSize = 64;
  std::array<std::int64_t, kSize> seq = filled(-1);  ///< seq held in each slot (-1: none)
  std::array<AttitudeMeasurement, kSize> att{};
  std::int64_t newest = -1;                          ///< newest seq noted

 private:
  static std::array<std::int64_t, kSize> filled(std::int64_t v) {
    std::array<std::int64_t, kSize> a;
    a.fill(v);
    return a;
  }
};

/// What the controller sees each period.
struct Measurement {
  double t = 0.0;             ///< time of the sample [s] (profile time)
  Vec2 theta = Vec2::Zero();  ///< encoder angles theta1, theta2 [rad] (quantized)
  Vec2 dtheta = Vec2::Zero(); ///< reported rates [rad/s] (used when rate_source = status)
  AttitudeMeasurement att;    ///< base attitude sensors (default: no star sample, zero rate)
};

/// Memory between calls (the controller's "State"); copyable, reset by assignment.
struct ControllerState {
  Vec2 integral = Vec2::Zero();    ///< integral term I [N m]
  Vec2 theta_prev = Vec2::Zero();  ///< last encoder angles [rad]
  double t_prev = 0.0;             ///< time of theta_prev [s]
  Vec2 rate = Vec2::Zero();        ///< filtered rate estimate [rad/s]
  bool primed = false;             ///< theta_prev holds a sample
  AttitudeEstimatorState estimator; ///< base attitude estimate
  Vec3 gyro_prev = Vec3::Zero();   ///< last gyro rate used [rad/s]
  Vec2 ref_prev = Vec2::Zero();    ///< last IK solution (branch continuity) [rad]
  Vec3 omega_B_prev = Vec3::Zero(); ///< last bias-corrected base rate [rad/s]
  Vec3 alpha_B = Vec3::Zero();     ///< filtered base angular acceleration, base frame [rad/s^2]
  double t_alpha_prev = 0.0;       ///< time of omega_B_prev [s]
  bool ref_primed = false;         ///< ref_prev / gyro_prev / estimator.t hold a period
  long long gyro_missing = 0;      ///< periods with the gyro rate held
  long long star_outage_periods = 0; ///< periods with the star tracker in outage
  MonitorState monitor;            ///< fault detection (fault_monitor.hpp); monitor.suspect[i]: axis i on rate feedback only
  AttitudeHistory attitudes;       ///< recent attitude messages (noteAttitude, closed_loop.hpp)
  Vec2 last_tau = Vec2::Zero();    ///< the last command computed [N m]: held when a reading is rejected
  Vec2 tau_ff_prev = Vec2::Zero(); ///< last feed-forward torque before the lead [N m] (t_prev: its time)
  PlayGuardState play;             ///< backlash guard (play_guard.hpp)
  TrackerFusionState fusion;       ///< the antenna tracker's play offset (tracker_fusion.hpp)
  long long rejected_readings = 0; ///< measurements with a NaN or Inf: the whole one (time, angle, rate) or its gyro or star sample
};

/// One update's result; tau is the command.
struct ControlOutput {
  Vec2 tau = Vec2::Zero();         ///< commanded torque, limited [N m]
  Vec2 tau_unsat = Vec2::Zero();   ///< before the limit [N m]
  Vec2 error = Vec2::Zero();       ///< q_ref - theta - load_offset [rad]
  Vec2 rate = Vec2::Zero();        ///< rate used in the derivative term [rad/s]
  ProfileSample ref;               ///< the joint reference tracked (inertial: IK; joint: the profile)
  Vec2 accel_ff = Vec2::Zero();    ///< the acceleration the feed-forward torque J_i a_i is for [rad/s^2]
  Vec2 tau_ff = Vec2::Zero();      ///< feed-forward torque at the measurement time, before the lead [N m]
  std::array<bool, 2> saturated{}; ///< |tau_unsat| > limit
  std::array<bool, 2> in_play{};   ///< the axis stepped on its play gains (play_guard.hpp)
  Vec2 load_offset = Vec2::Zero(); ///< [rad] the play's offset from the antenna tracker the error used (tracker_fusion.hpp)
  ProfileSample profile;           ///< the profile at the measurement time
  Quat q_WB_est = Quat::Identity();///< estimated base attitude, base -> inertial
  Vec3 omega_B_est = Vec3::Zero(); ///< bias-corrected base rate used [rad/s]
  bool star_outage = false;        ///< star tracker outage: the estimate coasts on the gyro
  bool ik_singular = false;        ///< target along the azimuth axis (keyhole)
  bool rejected = false;           ///< the measurement had a NaN or Inf: state kept, last command held
};

/// Inertial mode: the estimator step and the joint reference (q, dq from the
/// IK, ddq = the profile's) into out (ref, profile, estimate, flags); joint
/// mode: ref = profile (the estimator still runs, for the log). noexcept, no allocation.
void jointReference(const ControllerConfig& c, ControllerState& s, const Measurement& meas,
                    ControlOutput& out) noexcept;

/// One control period. A non-finite time, angle or rate is rejected: the
/// state is kept, the last command held, out.rejected set and the reading
/// counted (s.rejected_readings); a non-finite gyro or star sample alone is
/// dropped (counted) and the period runs without it. One bad reading never
/// enters the integral, the filter or the estimate.
ControlOutput update(const ControllerConfig& c, ControllerState& s, const Measurement& meas) noexcept;

/// Gains placing the closed-loop poles of J s^3 + kd s^2 + kp s + ki at a
/// triple pole -omega (kd = 3 J w, kp = 3 J w^2, ki = J w^3); inertia = J.
AxisGains triplePoleGains(double J, double omega, double torque_limit, double aw_gain);

}  // namespace gimbalsim::controllers
