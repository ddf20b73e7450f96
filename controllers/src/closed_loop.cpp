#include "gimbalsim/controllers/closed_loop.hpp"

#include <algorithm>
#include <limits>
#include <cmath>
#include <stdexcept>

#include "gimbalsim/dynamics/simulate.hpp"
#include "gimbalsim/firmware_sim/firmware.hpp"

namespace gimbalsim::controllers {
namespace {

/// Running figures of a run (ClosedLoopResult), fed one tick at a time.
class Figures {
 public:
  Figures(const TargetProfile& p, const ClosedLoopOptions& opt) : p_(p), opt_(opt), last_unsettled_(p.slewEnd()) {}

  void add(const TickRecord& rec, double period, bool saturated, ClosedLoopResult& r) {
    const double ej = (rec.ref.q - rec.theta_true).cwiseAbs().maxCoeff();
    switch (rec.ref.segment) {
      case Segment::Wait: break;
      case Segment::Slew: r.max_joint_error_slew = std::max(r.max_joint_error_slew, ej); break;
      case Segment::Hold:
        hold_seen_ = true;
        r.max_joint_error_hold = std::max(r.max_joint_error_hold, ej);
        if (ej >= opt_.settle_tol) last_unsettled_ = rec.t + period;
        r.max_truth_error_hold_end = rec.truth_error;
        break;
      case Segment::Track:
        r.max_joint_error_track = std::max(r.max_joint_error_track, ej);
        r.max_truth_error_track = std::max(r.max_truth_error_track, rec.truth_error);
        sum_sq_ += rec.truth_error * rec.truth_error;
        ++n_track_;
        break;
    }
    r.max_abs_tau = r.max_abs_tau.cwiseMax(rec.tau_applied.cwiseAbs());
    r.max_attitude_error = std::max(r.max_attitude_error, rec.attitude_error);
    if (rec.star_outage) ++r.star_outage_ticks;
    if (saturated) ++r.saturated_ticks;
  }

  void finish(ClosedLoopResult& r) const {
    if (hold_seen_ && last_unsettled_ < p_.trackStart()) r.settle_time = last_unsettled_ - p_.slewEnd();
    if (n_track_ > 0) r.rms_truth_error_track = std::sqrt(sum_sq_ / static_cast<double>(n_track_));
  }

 private:
  const TargetProfile& p_;
  const ClosedLoopOptions& opt_;
  double last_unsettled_;  ///< last hold time with the error outside the band
  bool hold_seen_ = false;
  double sum_sq_ = 0.0;
  long long n_track_ = 0;
};

template <class V>
ClosedLoopResult run(const Scene& sc, const ControllerConfig& c, const firmware::Config& fc,
                     const ClosedLoopOptions& opt, const std::function<void(const TickRecord&)>& sink) {
  ClosedLoopResult r;
  firmware::Firmware<V> fw(sc, fc, &c.profile, opt.faults);
  ControllerState cs;
  Figures fig(c.profile, opt);
  std::int64_t next_seq = 0;
  // Refused before the loop: llround of a tick count beyond long long is undefined.
  if (!(opt.duration / c.period <= 1e12)) {
    throw std::invalid_argument("closed loop: duration / control.period is more than 1e12 ticks");
  }
  Answer last;  // the controller's last answer (what the record shows while no status comes)
  const long long ticks = std::llround(opt.duration / c.period);
  for (long long k = 0; k <= ticks; ++k) {
    // The firmware's tick k up to its status and truth, as firmware_sim --lockstep.
    const std::int64_t utime = std::llround(static_cast<double>(k) * c.period * 1e6);
    fw.sample(utime);
    const contract::Status& st = fw.status();
    const contract::Truth& truth = fw.truth();
    // The controller answers the status delivered this tick, as pointing_controller
    // does; none when the fault schedule dropped or still holds it.
    const bool delivered = fw.statusDelivered();
    Answer a = last;
    a.flags = MonitorFlags{};
    if (delivered) {
      last = a = answerStatus(c, cs, st, fw.attitude(), next_seq);
    } else {
      noteAttitude(cs, fw.attitude());  // the attitude message still came
    }

    TickRecord rec;
    rec.answered = delivered;
    rec.flags = a.flags;
    rec.injected_faults = truth.injected_faults;
    rec.momentum_linear = Vec3(truth.momentum_linear[0], truth.momentum_linear[1], truth.momentum_linear[2]);
    rec.momentum_angular = Vec3(truth.momentum_angular[0], truth.momentum_angular[1], truth.momentum_angular[2]);
    rec.t = static_cast<double>(k) * c.period;
    rec.ref = a.out.ref;
    rec.theta_true = {truth.joint_angle[0], truth.joint_angle[1]};
    rec.theta_meas = a.meas.theta;
    rec.tau_cmd = a.out.tau;
    rec.tau_applied = {st.applied_torque[0], st.applied_torque[1]};
    rec.truth_error = truth.pointing_error;
    rec.profile = a.out.profile;
    rec.q_WB_est = a.out.q_WB_est;
    const double* bq = truth.base_quaternion;
    rec.q_WB_true = Quat(bq[0], bq[1], bq[2], bq[3]);
    rec.attitude_error = logRotation(rec.q_WB_true.conjugate() * rec.q_WB_est).norm();
    rec.star_outage = a.out.star_outage;
    fig.add(rec, c.period, a.out.saturated[0] || a.out.saturated[1], r);
    if (sink) sink(rec);
    r.ticks = k + 1;
    r.t_end = rec.t;
    if (k == ticks) break;
    fw.advance();
    if (fw.plantFault()) {
      r.ok = false;
      r.stop_status = fw.plantStatus();
      r.error = std::string(describe(fw.plantStatus())) + " at t = " + std::to_string(fw.plantFailTime()) + " s";
      return r;
    }
    // The answer arrives while (lockstep: after) the plant advances and acts
    // from tick k + 1 (the bus).
    if (delivered) fw.receive(a.cmd);
  }
  fig.finish(r);
  return r;
}

}  // namespace

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
  a.flags = observeStatus(c.monitor, s.monitor, c.period, st.seq, st.angle, st.rate, s.attitudes.newest,
                          att.star_outage != 0);
  const Vec2 integral = s.integral;
  a.out = update(c, s, a.meas);
  if (a.flags.stale) {  // hold the last command from a fresh status (safe torque after hold_ticks); no integration
    s.integral = integral;
    for (int i = 0; i < 2; ++i) a.out.tau(i) = a.flags.safe ? 0.0 : s.monitor.hold_tau[i];
  } else {
    for (int i = 0; i < 2; ++i) s.monitor.hold_tau[i] = a.out.tau(i);
  }
  a.cmd.utime = st.utime;
  // Saturating: an extreme last_command_seq (a bug, a spoofed status) must not overflow.
  constexpr std::int64_t kMaxSeq = std::numeric_limits<std::int64_t>::max();
  a.cmd.seq = std::max(next_seq, st.last_command_seq < kMaxSeq ? st.last_command_seq + 1 : kMaxSeq);
  next_seq = a.cmd.seq < kMaxSeq ? a.cmd.seq + 1 : kMaxSeq;
  a.cmd.status_seq = st.seq;
  a.cmd.mode = contract::kModeTorque;
  a.cmd.torque[0] = a.out.tau(0);
  a.cmd.torque[1] = a.out.tau(1);
  return a;
}

ClosedLoopResult runClosedLoop(const Scene& sc, const ControllerConfig& c, const ClosedLoopOptions& opt,
                               const std::function<void(const TickRecord&)>& sink) {
  firmware::Config fc;
  fc.control_period = c.period;
  if (const firmware::ConfigCheck chk = firmware::checkConfig(sc, fc); !chk.ok()) {
    ClosedLoopResult r;
    r.ok = false;
    r.error = "control.period: " + chk.message;
    return r;
  }
  return dispatchVariant(sc.model, [&](auto tag) { return run<decltype(tag)>(sc, c, fc, opt, sink); });
}

}  // namespace gimbalsim::controllers
