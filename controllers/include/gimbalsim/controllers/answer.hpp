// The controller's side of one tick, the same for pointing_controller (over
// LCM) and the in-process loop (PointingController, pointing_controller.hpp):
// the measurement of a status, the fault monitor, update() and the command.
#pragma once

#include <cstdint>

#include "gimbalsim/contract/messages.hpp"
#include "gimbalsim/controllers/fault_monitor.hpp"
#include "gimbalsim/controllers/pid.hpp"

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
/// answering it (status_seq = st.seq; seq = next_seq, the controller's own
/// strictly increasing counter, whatever the status's last_command_seq says;
/// utime = the status's). Before the law the fault monitor (fault_monitor.hpp) looks
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

}  // namespace gimbalsim::controllers
