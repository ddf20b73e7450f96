// A controller closed on the plant in one process, as the bench runs it:
// the firmware model (Firmware<V>, firmware.hpp: encoders quantized to
// sensors.encoder_resolution with the scene's optional noise, command
// validation, watchdog, saturation at torque.limit, one-tick bus latency,
// zero-order hold, RK4 sub-steps) ticks, and each tick the controller port
// (contract/controller_port.hpp) answers its status with a command, exactly
// as pointing_controller answers firmware_sim --lockstep over LCM (so the
// truth is bit for bit the same; tests/controllers/lockstep_matches_in_process_test).
// The truth pointing error is the observer's (pointing/truth_observer.hpp).
// The caller wires a controller to it (the plant never includes one). Used by
// the tests, the Python package and the tools; not a real-time path (the
// per-tick sink is a std::function).
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "gimbalsim/contract/controller_port.hpp"
#include "gimbalsim/dynamics/step_result.hpp"
#include "gimbalsim/firmware_sim/fault_schedule.hpp"
#include "gimbalsim/firmware_sim/plant_scene.hpp"
#include "gimbalsim/pointing/target_profile.hpp"

namespace gimbalsim::firmware {

/// One control tick, for logs. ref is the joint reference tracked (inertial
/// mode: the IK's), so joint errors are tracking errors.
struct TickRecord {
  double t = 0.0;                  ///< [s]
  pointing::ProfileSample ref;     ///< the joint reference the controller tracked (its report)
  Vec2 theta_true = Vec2::Zero();  ///< [rad] true joint angles
  Vec2 theta_meas = Vec2::Zero();  ///< [rad] encoder angles of the status
  Vec2 tau_cmd = Vec2::Zero();     ///< [N m] computed this tick
  Vec2 tau_applied = Vec2::Zero(); ///< [N m] acting over [t, t + Ts]
  double truth_error = 0.0;        ///< [rad] boresight vs the profile's line of sight (TruthObserver)
  /// [rad] rotation vector (inertial) from the target line of sight to the
  /// true boresight, |.| = truth_error: a vector, so window means (RPE, PDE) mean something.
  Vec3 los_error_true = Vec3::Zero();
  /// [rad] the same for the boresight the controller believes in (its base
  /// attitude estimate and the encoder angles, plus the play's offset its
  /// antenna tracker measured): knowledge error = est - true.
  Vec3 los_error_est = Vec3::Zero();
  pointing::ProfileSample profile; ///< the target profile at t (the truth observer's)
  Quat q_WB_est = Quat::Identity();///< estimated base attitude
  Quat q_WB_true = Quat::Identity();///< true base attitude
  double attitude_error = 0.0;     ///< [rad] angle between the estimated and true base attitudes
  bool star_outage = false;        ///< the star tracker was in an outage (the estimate coasts)
  bool answered = true;            ///< false: no status delivered this tick (fault schedule), no command sent
  contract::MonitorFlags flags;    ///< the controller's fault monitor for this status (its report)
  std::int64_t injected_faults = 0;  ///< the faults scheduled in the plant this tick (truth)
  Vec3 momentum_linear = Vec3::Zero();   ///< [N s] truth, inertial
  Vec3 momentum_angular = Vec3::Zero();  ///< [N m s] truth, about the inertial origin
  /// [rad] truth: tilt angle gamma of joint 1's, joint 2's journal (0 unless
  /// spatial clearance): play between the encoder and the antenna
  Vec2 tilt = Vec2::Zero();
  /// [rad] the antenna tracker's reading (u, v: antenna_sensors.hpp), the
  /// last one delivered; NaN with no antenna sensors (sensors.antenna none)
  /// and before the first delivery
  Vec2 tracker = Vec2::Constant(std::numeric_limits<double>::quiet_NaN());
};

/// Where a closed-loop run's time went (ClosedLoopOptions::cost): [s] of
/// steady-clock wall time, for the benchmark that weighs the tick's own work
/// (controller, sensors, observer, records) against the plant's stepping.
struct ClosedLoopCost {
  double step_s = 0.0;        ///< the plant's stepping (BenchTick::advance: RK4 and its sub-steps)
  double controller_s = 0.0;  ///< the controller port's turn (answer, noteAttitude, noteAntenna)
  double total_s = 0.0;       ///< the whole run, from the first tick to the figures
  long long ticks = 0;        ///< ticks run
};

struct ClosedLoopOptions {
  double duration = 10.0;          ///< [s]
  double settle_tol = 1.0e-3;      ///< [rad] band on max |q_ref - theta| per axis for "settled"
  /// Faults the plant injects (null: none), as firmware_sim --faults; must outlive the run.
  const FaultSchedule* faults = nullptr;
  /// Filled with where the run's time went (null: nothing measured, no clock read); must outlive the run.
  ClosedLoopCost* cost = nullptr;
  /// Asked every kStopCheckTicks ticks (null: never asked): true ends the run
  /// there, interrupted (a program's SIGINT/SIGTERM flag, io::stopRequested).
  bool (*stop_requested)() noexcept = nullptr;
};
inline constexpr long long kStopCheckTicks = 1024;  ///< a long run stops within about a second of CPU

/// Figures of one closed-loop run. Joint errors use the true angles. A
/// figure over a window of the profile (pointing/profile_windows.hpp) the run
/// did not reach is NaN and its window's reason says why (docs/usage.md
/// "Figures over a window"); the run itself stays ok.
struct ClosedLoopResult {
  bool ok = true;
  std::string error;               ///< why the plant stopped (StepStatus), the run was refused or interrupted, if !ok
  bool interrupted = false;        ///< ClosedLoopOptions::stop_requested ended it (!ok, t_end where)
  StepStatus stop_status = StepStatus::Ok;  ///< the plant's step status when it stopped
  /// When the plant stopped, as the bench says it: "the plant stopped after t = " describeStopWhen ": "
  /// describeStopCause (its last good state's time, not error's failed step); empty if it did not.
  std::string plant_stop;
  /// Why the run ended !ok, as a study names it: plant_stop when the plant stopped, else error.
  const std::string& stopReason() const noexcept { return plant_stop.empty() ? error : plant_stop; }
  double t_end = 0.0;              ///< [s]
  /// [s] after the slew's end until max |joint error| stays below settle_tol
  /// for the rest of the hold; NaN with settle_reason if it never does before
  /// tracking starts, or the run did not reach the hold's end.
  double settle_time = std::numeric_limits<double>::quiet_NaN();
  double max_joint_error_slew = 0.0;   ///< [rad] during the slew
  double max_joint_error_hold = 0.0;   ///< [rad] during the hold (overshoot and settling)
  double max_joint_error_track = 0.0;  ///< [rad] during tracking
  double max_truth_error_track = 0.0;  ///< [rad] truth pointing error during tracking
  double rms_truth_error_track = 0.0;  ///< [rad]
  double max_truth_error_hold_end = 0.0;  ///< [rad] at the end of the hold
  /// Why the figures of a window are NaN ("" when they have values): slew
  /// (max_joint_error_slew), hold (max_joint_error_hold), hold_end
  /// (max_truth_error_hold_end, settle_time), track (the three *_track).
  std::string slew_reason, hold_reason, hold_end_reason, track_reason;
  /// Why settle_time is NaN ("" when it has a value): the hold's end unreached, or never settled.
  std::string settle_reason;
  /// Why the whole-run figures (max_abs_tau, max_attitude_error, a spatial
  /// joint's max_tilt; one that cannot tilt keeps 0) are NaN: no tick was
  /// recorded, or only the first and the plant's step from it failed ("" when
  /// they have values).
  std::string run_reason;
  Vec2 max_abs_tau = Vec2::Zero();     ///< [N m] applied
  /// The two limits a torque meets (docs/usage.md "Torque limits"): ticks
  /// whose command the controller held at its own limit (azimuth/elevation.torque_limit),
  /// and ticks whose applied torque the plant's motor limit (torque.limit) clipped; either axis.
  long long controller_limited_ticks = 0;
  long long motor_limited_ticks = 0;
  /// controller_limited_ticks while tracking: a slew may saturate by design, a track should not
  long long controller_limited_ticks_track = 0;
  double max_attitude_error = 0.0;     ///< [rad] estimated vs true base attitude, whole run
  Vec2 max_tilt = Vec2::Zero();        ///< [rad] largest tilt of each joint's journal at the ticks, whole run
  /// [s] the first tick at which each axis ran on its backlash guard's gains
  /// (the controller saw a play, controllers' play_guard.hpp); NaN: never
  Vec2 play_onset = Vec2::Constant(std::numeric_limits<double>::quiet_NaN());
  long long star_outage_ticks = 0;     ///< ticks the controller flagged a star tracker outage
  long long rejected_readings = 0;     ///< statuses whose reading the controller rejected (NaN or Inf)
  long long commands_rejected = 0;     ///< commands the plant rejected (firmware's checks: sanity range, NaN, ...)
  /// The plant accepted none of the controller's commands over kStatusesToJudge
  /// answered statuses or more, or rejected kRejectedInARow in a row (where the
  /// lockstep bench ends the run, exit 3): the run did not control it (ok = false, error says why).
  bool rejected_stop = false;
  long long ticks = 0;
};

/// Why a controller ticking every control_period [s] cannot run on the
/// plant scene ps ("" when it can: a whole multiple of sim.step, as
/// checkConfig wants); the tools refuse it before any run (exit 2).
std::string controlPeriodProblem(const PlantScene& ps, double control_period);

/// Runs the controller on the plant for opt.duration (ticks 0 ..
/// round(duration / period), the last one not stepped); the truth pointing
/// error is against `profile` (the controller's target), whose segments
/// (slew, hold, track) the figures use. The plant's constant scene torques
/// are ignored: the controller is the only input. The firmware runs with its
/// default settings (Config) at the controller's period, which must be a
/// whole multiple of sim.step (else !ok, nothing run). A NaN or Inf in a
/// tick's record (command, measurement, truth, estimate) stops the run there
/// (!ok, stop_status NonFinite, error naming the value and the time): the
/// figures cover the finite ticks before it only.
ClosedLoopResult runClosedLoop(const PlantScene& ps, contract::ControllerPort& controller,
                               const pointing::TargetProfile& profile, const ClosedLoopOptions& opt,
                               const std::function<void(const TickRecord&)>& sink = {});

}  // namespace gimbalsim::firmware
