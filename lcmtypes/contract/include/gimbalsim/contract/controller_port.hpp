// The controller as the plant's peer in one process: the port a controller
// implements and the in-process closed loop (firmware_sim/closed_loop.hpp)
// drives, the same exchange as over LCM (status and attitude in, command
// out), plus what the controller reports of its own tick for logs. The
// caller wires a controller to the loop, so neither side includes the other.
#pragma once

#include <cstdint>

#include "gimbalsim/contract/messages.hpp"
#include "gimbalsim/pointing/target_profile.hpp"

namespace gimbalsim::contract {

/// What a controller's fault monitor concluded for one status.
struct MonitorFlags {
  bool stale = false;                 ///< status older than stale_ticks: command held
  bool safe = false;                  ///< stale for more than hold_ticks: safe (zero) torque
  bool encoder_suspect[2] = {};       ///< axis runs on rate feedback only
  bool star_outage = false;           ///< the star tracker reports an outage
  std::int64_t age = 0;               ///< [ticks] newest attitude seq - status seq (0 if not older)
};

/// The controller's account of one answer, beside its command.
struct ControllerReport {
  pointing::ProfileSample ref;         ///< the joint reference tracked (inertial mode: the IK's)
  Vec2 theta_meas = Vec2::Zero();      ///< [rad] encoder angles it used
  /// [rad] the play's offset (antenna minus encoders, joint coordinates) its
  /// antenna tracker last measured; 0 without one: it believes the antenna
  /// at theta_meas + antenna_offset
  Vec2 antenna_offset = Vec2::Zero();
  Vec2 tau_cmd = Vec2::Zero();         ///< [N m] torque it commanded
  Quat q_WB_est = Quat::Identity();    ///< estimated base attitude, base -> inertial
  bool star_outage = false;            ///< the attitude estimate coasts on the gyro
  bool saturated[2] = {};              ///< the command hit the controller's own limit, per axis
  bool in_play[2] = {};                ///< the axis runs on its backlash guard's gains (a play seen), per axis
  MonitorFlags flags;                  ///< its fault monitor's view of the status
  bool reading_rejected = false;       ///< a NaN or Inf in the status or its attitude: rejected, the last command held
};

/// A controller, as the in-process loop sees it. Calls are noexcept and
/// allocation-free (the loop's tick is).
class ControllerPort {
 public:
  virtual ~ControllerPort() = default;
  /// [s] the period the controller runs at; the plant ticks at it.
  virtual double period() const noexcept = 0;
  /// The command answering status st, with att the newest attitude message
  /// (the same tick's, or older when the status came late); fills report.
  virtual Command answer(const Status& st, const Attitude& att, ControllerReport& report) noexcept = 0;
  /// An attitude message that came without a status this tick.
  virtual void noteAttitude(const Attitude& att) noexcept = 0;
  /// The antenna sensors' message of a tick (a plant with them sends it
  /// before the tick's status); a controller that does not use them ignores it.
  virtual void noteAntenna(const Antenna& /*antenna*/) noexcept {}
};

}  // namespace gimbalsim::contract
