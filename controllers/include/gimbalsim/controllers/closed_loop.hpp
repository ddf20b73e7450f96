// The controller closed on the plant in one process, as the bench runs it:
// the firmware model (firmware::Firmware<V>, firmware.hpp: encoders quantized
// to sensors.encoder_resolution with the scene's optional noise, command
// validation, watchdog, saturation at torque.limit, one-tick bus latency,
// zero-order hold, RK4 sub-steps) ticks, and each tick the controller's
// update() reads its status and answers with a command, exactly as
// pointing_controller answers firmware_sim --lockstep over LCM (so the truth
// is bit for bit the same; tests/controllers/lockstep_matches_in_process_test).
// Used by the tests and by the in-process gain sweep; not a real-time path
// (the per-tick sink is a std::function).
#pragma once

#include <functional>
#include <limits>
#include <string>

#include "gimbalsim/controllers/fault_monitor.hpp"
#include "gimbalsim/controllers/pid.hpp"
#include "gimbalsim/dynamics/run_spec.hpp"
#include "gimbalsim/dynamics/step_result.hpp"
#include "gimbalsim/firmware_sim/fault_schedule.hpp"
#include "gimbalsim/contract/messages.hpp"

namespace gimbalsim::controllers {

/// The controller's answer to one status.
struct Answer {
  Measurement meas;      ///< what update() saw
  ControlOutput out;     ///< what it computed
  contract::Command cmd; ///< the command answering the status
  MonitorFlags flags;    ///< what the fault monitor saw, and whether the command is held or safe
};

/// The controller's side of a tick, the same for pointing_controller (over
/// LCM) and the in-process loop: the measurement of status st (profile time
/// st.seq * period, encoder angles, rates), update(), and the torque command
/// answering it (status_seq = st.seq; seq strictly increasing and above the
/// last seq the firmware accepted, even after a controller restart; utime =
/// the status's). Before the law the fault monitor (fault_monitor.hpp) looks
/// at the status against att.seq: a stale status gets the held command (or
/// the safe one), a suspect encoder rate feedback only on its axis.
/// att is the newest attitude message received: used when
/// att.seq == st.seq (the same tick); otherwise the gyro sample counts as
/// missing (the previous rate is held, ControllerState::gyro_missing) and no
/// star sample is used. next_seq is the caller's counter (start at 0). No allocation.
Answer answerStatus(const ControllerConfig& c, ControllerState& s, const contract::Status& st,
                    const contract::Attitude& att, std::int64_t& next_seq) noexcept;

/// Keeps an attitude message (every one received, also while no status
/// comes) in s.attitudes; answerStatus() notes the one it is given too.
void noteAttitude(ControllerState& s, const contract::Attitude& att) noexcept;

/// The controller's view of an attitude message of tick seq (see answerStatus).
AttitudeMeasurement attitudeMeasurement(const contract::Attitude& att, std::int64_t seq) noexcept;

/// One control tick, for logs. ref is the joint reference tracked (inertial
/// mode: the IK's), so joint errors are tracking errors.
struct TickRecord {
  double t = 0.0;                  ///< [s]
  ProfileSample ref;               ///< reference at t
  Vec2 theta_true = Vec2::Zero();  ///< [rad] true joint angles
  Vec2 theta_meas = Vec2::Zero();  ///< [rad] encoder angles of the status
  Vec2 tau_cmd = Vec2::Zero();     ///< [N m] computed this tick
  Vec2 tau_applied = Vec2::Zero(); ///< [N m] acting over [t, t + Ts]
  double truth_error = 0.0;        ///< [rad] boresight vs losBoresight(profile)
  ProfileSample profile;           ///< the profile at t (ref is the joint reference tracked: = profile in joint mode)
  Quat q_WB_est = Quat::Identity();///< estimated base attitude
  Quat q_WB_true = Quat::Identity();///< true base attitude
  double attitude_error = 0.0;     ///< [rad] angle between the estimated and true base attitudes
  bool star_outage = false;        ///< the star tracker was in an outage (the estimate coasts)
  bool answered = true;            ///< false: no status delivered this tick (fault schedule), no command sent
  MonitorFlags flags;              ///< the controller's fault monitor for this status
  std::int32_t injected_faults = 0;///< the faults scheduled in the plant this tick (truth)
  Vec3 momentum_linear = Vec3::Zero();   ///< [N s] truth, inertial
  Vec3 momentum_angular = Vec3::Zero();  ///< [N m s] truth, about the inertial origin
};

struct ClosedLoopOptions {
  double duration = 10.0;          ///< [s]
  double settle_tol = 1.0e-3;      ///< [rad] band on max |q_ref - theta| per axis for "settled"
  /// Faults the plant injects (null: none), as firmware_sim --faults; must outlive the run.
  const firmware::FaultSchedule* faults = nullptr;
};

/// Figures of one closed-loop run. Joint errors use the true angles.
struct ClosedLoopResult {
  bool ok = true;
  std::string error;               ///< why the plant stopped (StepStatus) or the run was refused, if !ok
  StepStatus stop_status = StepStatus::Ok;  ///< the plant's step status when it stopped
  double t_end = 0.0;              ///< [s]
  /// [s] after the slew's end until max |joint error| stays below settle_tol
  /// for the rest of the hold; +inf if it never does before tracking starts.
  double settle_time = std::numeric_limits<double>::infinity();
  double max_joint_error_slew = 0.0;   ///< [rad] during the slew
  double max_joint_error_hold = 0.0;   ///< [rad] during the hold (overshoot and settling)
  double max_joint_error_track = 0.0;  ///< [rad] during tracking
  double max_truth_error_track = 0.0;  ///< [rad] truth pointing error during tracking
  double rms_truth_error_track = 0.0;  ///< [rad]
  double max_truth_error_hold_end = 0.0;  ///< [rad] at the end of the hold
  Vec2 max_abs_tau = Vec2::Zero();     ///< [N m] applied
  long long saturated_ticks = 0;       ///< ticks with a limited command (either axis)
  double max_attitude_error = 0.0;     ///< [rad] estimated vs true base attitude, whole run
  long long star_outage_ticks = 0;     ///< ticks the controller flagged a star tracker outage
  long long ticks = 0;
};

/// Runs the configured controller on the scene for opt.duration (ticks 0 ..
/// round(duration / period), the last one not stepped). The plant's constant
/// scene torques are ignored: the controller is the only input. The firmware
/// runs with its default settings (firmware::Config) at the controller's
/// period, which must be a whole multiple of sim.step (else !ok, nothing run).
ClosedLoopResult runClosedLoop(const Scene& sc, const ControllerConfig& c, const ClosedLoopOptions& opt,
                               const std::function<void(const TickRecord&)>& sink = {});

}  // namespace gimbalsim::controllers
