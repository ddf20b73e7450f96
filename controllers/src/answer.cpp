#include "gimbalsim/controllers/answer.hpp"

#include <algorithm>
#include <limits>

namespace gimbalsim::controllers {

AttitudeMeasurement attitudeMeasurement(const contract::Attitude& att, std::int64_t seq) noexcept {
  AttitudeMeasurement m;
  m.star_outage = att.star_outage != 0;
  if (att.seq != seq) {  // not this tick's: hold the previous rate, no star sample
    m.gyro_valid = false;
    return m;
  }
  m.gyro = {att.gyro_rate[0], att.gyro_rate[1], att.gyro_rate[2]};
  m.star_valid = att.star_valid != 0;
  m.star_time = att.star_time;
  const double* q = att.star_quaternion;
  m.star_q = Quat(q[0], q[1], q[2], q[3]);
  return m;
}

void noteAttitude(ControllerState& s, const contract::Attitude& att) noexcept {
  if (att.seq < 0) return;
  const int i = static_cast<int>(att.seq % AttitudeHistory::kSize);
  s.attitudes.seq[i] = att.seq;
  s.attitudes.att[i] = attitudeMeasurement(att, att.seq);
  s.attitudes.newest = std::max(s.attitudes.newest, att.seq);
}

Answer answerStatus(const ControllerConfig& c, ControllerState& s, const contract::Status& st,
                    const contract::Attitude& att, std::int64_t& next_seq) noexcept {
  Answer a;
  a.meas.t = static_cast<double>(st.seq) * c.period;
  a.meas.theta = {st.angle[0], st.angle[1]};
  a.meas.dtheta = {st.rate[0], st.rate[1]};
  noteAttitude(s, att);
  // The attitude of the status's own tick (a late status finds it in the history).
  const int slot = static_cast<int>((st.seq >= 0 ? st.seq : 0) % AttitudeHistory::kSize);
  a.meas.att = s.attitudes.seq[slot] == st.seq ? s.attitudes.att[slot] : attitudeMeasurement(att, st.seq);
  // A reading with a NaN or Inf is rejected by update() (last command held);
  // the fault monitor does not see it either.
  const bool finite = a.meas.theta.allFinite() && a.meas.dtheta.allFinite();
  if (finite) {
    a.flags = observeStatus(c.monitor, s.monitor, c.period, st.seq, st.angle, st.rate, s.attitudes.newest,
                            att.star_outage != 0);
  }
  const Vec2 integral = s.integral;
  a.out = update(c, s, a.meas);
  // A law that overflowed on a finite reading (an angle of 1e308) gives no command: its saturated torque
  // carried the overflow's sign to the motor at full scale. Python's Controller.update refuses it too.
  const bool overflowed = !a.out.rejected && !(a.out.tau_unsat.allFinite() && a.out.error.allFinite());
  if (a.flags.stale) {  // hold the last command from a fresh status (safe torque after hold_ticks); no integration
    s.integral = integral;
    for (int i = 0; i < 2; ++i) a.out.tau(i) = a.flags.safe ? 0.0 : s.monitor.hold_tau[i];
  } else if (overflowed) {
    a.out.tau.setConstant(std::numeric_limits<double>::quiet_NaN());  // never sent (the bench), refused (in process)
  } else {
    for (int i = 0; i < 2; ++i) s.monitor.hold_tau[i] = a.out.tau(i);
  }
  a.cmd.utime = st.utime;
  // Our own counter only, never the status's last_command_seq: that may be a
  // stranger's extreme seq (one that held the plant's binding), and the plant
  // gives each new binding a fresh seq history (command_gate.hpp).
  a.cmd.seq = next_seq;
  if (next_seq < std::numeric_limits<std::int64_t>::max()) ++next_seq;
  a.cmd.status_seq = st.seq;
  a.cmd.mode = contract::kModeTorque;
  a.cmd.torque[0] = a.out.tau(0);
  a.cmd.torque[1] = a.out.tau(1);
  return a;
}

}  // namespace gimbalsim::controllers
