// The controller closed on the dynamics in one process, as the bench would
// run it: every control period the controller reads the encoder angles
// (quantized to the scene's sensors.encoder_resolution) and the rates, its
// torque reaches the plant one period later (one-tick bus latency), held
// constant over the period (zero-order hold) and saturated at the scene's
// torque.limit like the firmware does. Used by the tests and by the in-process
// gain sweep; not a real-time path (the per-tick sink is a std::function).
#pragma once

#include <functional>
#include <limits>
#include <string>

#include "gimbalsim/controllers/pid.hpp"
#include "gimbalsim/dynamics/integrator.hpp"
#include "gimbalsim/dynamics/observables.hpp"

namespace gimbalsim::controllers {

/// One control tick, for logs.
struct TickRecord {
  double t = 0.0;                  ///< [s]
  ProfileSample ref;               ///< reference at t
  Vec2 theta_true = Vec2::Zero();  ///< [rad] true joint angles
  Vec2 theta_meas = Vec2::Zero();  ///< [rad] quantized encoder angles
  Vec2 tau_cmd = Vec2::Zero();     ///< [N m] computed this tick
  Vec2 tau_applied = Vec2::Zero(); ///< [N m] acting over [t, t + Ts]
  double truth_error = 0.0;        ///< [rad] boresight vs losBoresight(ref)
};

struct ClosedLoopOptions {
  double duration = 10.0;          ///< [s]
  double settle_tol = 1.0e-3;      ///< [rad] band on max |q_ref - theta| per axis for "settled"
  bool one_tick_delay = true;      ///< command of tick k acts over tick k+1 (the bus)
};

/// Figures of one closed-loop run. Joint errors use the true angles.
struct ClosedLoopResult {
  bool ok = true;
  std::string error;               ///< why the plant stopped (StepStatus), if !ok
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
  long long ticks = 0;
};

/// Runs the configured controller on the scene for opt.duration. The plant's
/// constant scene torques are ignored: the controller is the only input.
ClosedLoopResult runClosedLoop(const Model& m, const ControllerConfig& c, const ClosedLoopOptions& opt,
                               const std::function<void(const TickRecord&)>& sink = {});

/// Encoder reading of a true angle: nearest multiple of the resolution (0: exact).
inline double quantize(double angle, double resolution) noexcept {
  return resolution > 0.0 ? resolution * std::nearbyint(angle / resolution) : angle;
}

}  // namespace gimbalsim::controllers
