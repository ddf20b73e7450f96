#include "gimbalsim/firmware_sim/closed_loop.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "gimbalsim/dynamics/simulate.hpp"
#include "gimbalsim/dynamics/variant.hpp"
#include "gimbalsim/firmware_sim/bench_tick.hpp"
#include "gimbalsim/firmware_sim/plant_stop.hpp"
#include "gimbalsim/input/key_registry.hpp"
#include "gimbalsim/pointing/profile_windows.hpp"
#include "gimbalsim/pointing/tracker_axes.hpp"

namespace gimbalsim::firmware {
namespace {

/// Every figure over a window the run did not reach (or, for a figure at
/// the window's end, whose end it did not reach) becomes NaN with the reason.
void markUnreached(const pointing::TargetProfile& p, const Model& m, ClosedLoopResult& r) {
  using pointing::Segment;
  using pointing::WindowNeed;
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  r.slew_reason = pointing::windowNotReached(pointing::profileWindow(p, Segment::Slew), WindowNeed::Part, r.t_end);
  r.hold_reason = pointing::windowNotReached(pointing::profileWindow(p, Segment::Hold), WindowNeed::Part, r.t_end);
  r.hold_end_reason = pointing::windowNotReached(pointing::profileWindow(p, Segment::Hold), WindowNeed::End, r.t_end);
  r.track_reason = pointing::windowNotReached(pointing::profileWindow(p, Segment::Track), WindowNeed::Part, r.t_end);
  if (!r.slew_reason.empty()) r.max_joint_error_slew = kNaN;
  if (!r.hold_reason.empty()) r.max_joint_error_hold = kNaN;
  if (!r.hold_end_reason.empty()) {
    r.max_truth_error_hold_end = r.settle_time = kNaN;
    r.settle_reason = r.hold_end_reason;
  }
  if (!r.track_reason.empty()) r.max_joint_error_track = r.max_truth_error_track = r.rms_truth_error_track = kNaN;
  // A max over no tick is no figure, never 0; nor is one over the first tick alone when the plant's first
  // step from it failed (run_reason set there): its torque never acted, its state the initial one (pass 53).
  if (r.ticks == 0 || !r.run_reason.empty()) {
    if (r.run_reason.empty()) r.run_reason = r.ok ? "no tick ran" : "no tick before the run stopped: " + r.error;
    r.max_abs_tau.setConstant(kNaN), r.max_attitude_error = kNaN;
    // a joint that cannot tilt has tilt 0 by construction, whatever ran (docs/usage.md; pass 55)
    for (int j = 0; j < 2; ++j) r.max_tilt(j) = m.jointKind(j) == ClearanceKind::Spatial ? kNaN : 0.0;
  }
}

/// Running figures of a run (ClosedLoopResult), fed one tick at a time.
class Figures {
 public:
  Figures(const pointing::TargetProfile& p, const Model& m, const ClosedLoopOptions& opt)
      : p_(p), m_(m), opt_(opt), last_unsettled_(p.slewEnd()) {}

  void add(const TickRecord& rec, double period, bool controller_limited, bool motor_limited, ClosedLoopResult& r) {
    const double ej = (rec.ref.q - rec.theta_true).cwiseAbs().maxCoeff();
    switch (rec.ref.segment) {
      case pointing::Segment::Wait: break;
      case pointing::Segment::Slew: r.max_joint_error_slew = std::max(r.max_joint_error_slew, ej); break;
      case pointing::Segment::Hold:
        hold_seen_ = true;
        r.max_joint_error_hold = std::max(r.max_joint_error_hold, ej);
        if (ej >= opt_.settle_tol) last_unsettled_ = rec.t + period;
        r.max_truth_error_hold_end = rec.truth_error;
        break;
      case pointing::Segment::Track:
        r.max_joint_error_track = std::max(r.max_joint_error_track, ej);
        r.max_truth_error_track = std::max(r.max_truth_error_track, rec.truth_error);
        sum_sq_ += rec.truth_error * rec.truth_error;
        ++n_track_;
        if (controller_limited) ++r.controller_limited_ticks_track;
        break;
    }
    r.max_abs_tau = r.max_abs_tau.cwiseMax(rec.tau_applied.cwiseAbs());
    r.max_attitude_error = std::max(r.max_attitude_error, rec.attitude_error);
    r.max_tilt = r.max_tilt.cwiseMax(rec.tilt);
    if (rec.star_outage) ++r.star_outage_ticks;
    if (controller_limited) ++r.controller_limited_ticks;
    if (motor_limited) ++r.motor_limited_ticks;
  }

  void finish(ClosedLoopResult& r) const {
    if (hold_seen_ && last_unsettled_ < p_.trackStart()) {
      r.settle_time = last_unsettled_ - p_.slewEnd();
    } else {  // a time that never came is no figure, never +inf or 0
      r.settle_reason = "the joint error did not stay below settle_tol " + formatNumber(opt_.settle_tol) +
                        " rad before tracking started at " + formatNumber(p_.trackStart()) + " s";
    }
    if (n_track_ > 0) r.rms_truth_error_track = std::sqrt(sum_sq_ / static_cast<double>(n_track_));
    markUnreached(p_, m_, r);
  }

 private:
  const pointing::TargetProfile& p_;
  const Model& m_;
  const ClosedLoopOptions& opt_;
  double last_unsettled_;  ///< last hold time with the error outside the band
  bool hold_seen_ = false;
  double sum_sq_ = 0.0;
  long long n_track_ = 0;
};

/// The first non-finite value of a tick's record ("" if none): what the
/// figures are computed over, so none of them silently skips a NaN.
const char* nonFinite(const TickRecord& r) {
  if (!r.tau_cmd.allFinite()) return "commanded torque";
  if (!r.tau_applied.allFinite()) return "applied torque";
  if (!r.theta_meas.allFinite()) return "measured joint angle";
  if (!r.theta_true.allFinite()) return "true joint angle";
  if (!r.ref.q.allFinite() || !r.ref.dq.allFinite() || !r.ref.ddq.allFinite()) return "joint reference";
  if (!std::isfinite(r.truth_error)) return "truth pointing error";
  if (!r.q_WB_est.coeffs().allFinite()) return "estimated base attitude";
  if (!std::isfinite(r.attitude_error)) return "attitude error";
  if (!r.los_error_true.allFinite() || !r.los_error_est.allFinite()) return "line-of-sight error vector";
  if (!r.tilt.allFinite()) return "journal tilt";
  return "";
}

/// Adds a scope's steady-clock time to one field of the run's cost, when it is measured.
class CostTimer {
 public:
  using Clock = std::chrono::steady_clock;
  CostTimer(ClosedLoopCost* cost, double ClosedLoopCost::*field)
      : cost_(cost), field_(field), t0_(cost ? Clock::now() : Clock::time_point{}) {}
  ~CostTimer() {
    if (cost_) cost_->*field_ += std::chrono::duration<double>(Clock::now() - t0_).count();
  }
  CostTimer(const CostTimer&) = delete;
  CostTimer& operator=(const CostTimer&) = delete;

 private:
  ClosedLoopCost* cost_;
  double ClosedLoopCost::*field_;
  Clock::time_point t0_;
};

template <class V>
ClosedLoopResult run(const PlantScene& ps, contract::ControllerPort& ctrl, const pointing::TargetProfile& profile,
                     const Config& fc, const ClosedLoopOptions& opt,
                     const std::function<void(const TickRecord&)>& sink) {
  ClosedLoopResult r;
  BenchTick<V> tick(ps, fc, opt.faults, &profile);
  Firmware<V>& fw = tick.firmware();
  const pointing::TruthObserver& observer = tick.observer();
  Figures fig(profile, ps.scene.model, opt);
  const double period = fc.control_period;
  // Refused before the loop: llround of a tick count beyond long long is undefined.
  if (!(opt.duration / period <= 1e12)) {
    throw std::invalid_argument("closed loop: duration / control.period is more than 1e12 ticks");
  }
  // Whole control periods, as every duration of the project: refused, never rounded.
  if (const std::string why = wholeMultipleProblem(opt.duration, period, "the control period (control.period)");
      !why.empty()) {
    throw std::invalid_argument("closed loop: duration " + formatNumber(opt.duration) + " s " + why);
  }
  const CostTimer whole(opt.cost, &ClosedLoopCost::total_s);
  contract::ControllerReport last;  // the controller's last report (what the record shows while no status comes)
  contract::Command cmd;
  const long long ticks = std::llround(opt.duration / period);
  long long rejected_in_a_row = 0;  // commands the plant rejected since it last accepted one
  Counters rejected_from;           // the counters before the first of them
  for (long long k = 0; k <= ticks; ++k) {
    // The bench tick k up to its messages, on lockstep's clock (utime = simulated time).
    const std::int64_t utime = std::llround(static_cast<double>(k) * period * 1e6);
    const TickMessages m = tick.sample(k, utime, true);
    const Status& st = fw.status();
    const double t = static_cast<double>(k) * period;
    const Truth& truth = *m.truth;
    // The transport: the controller port answers the status delivered this
    // tick, as pointing_controller does; none when the fault schedule dropped
    // or still holds it.
    const bool delivered = m.status != nullptr;
    contract::ControllerReport a = last;
    a.flags = contract::MonitorFlags{};
    {
      const CostTimer turn(opt.cost, &ClosedLoopCost::controller_s);
      if (m.antenna != nullptr) ctrl.noteAntenna(*m.antenna);  // sent before the status, as on the bench
      if (delivered) {
        cmd = ctrl.answer(st, fw.attitude(), a);
        last = a;
      } else {
        ctrl.noteAttitude(fw.attitude());  // the attitude message still came
      }
    }

    TickRecord rec;
    rec.answered = delivered;
    rec.flags = a.flags;
    rec.injected_faults = truth.injected_faults;
    rec.momentum_linear = Vec3(truth.momentum_linear[0], truth.momentum_linear[1], truth.momentum_linear[2]);
    rec.momentum_angular = Vec3(truth.momentum_angular[0], truth.momentum_angular[1], truth.momentum_angular[2]);
    rec.t = t;
    rec.ref = a.ref;
    rec.theta_true = {truth.joint_angle[0], truth.joint_angle[1]};
    rec.tilt = {truth.tilt[0], truth.tilt[1]};
    if (m.antenna != nullptr && m.antenna->tracker_time >= 0.0) {  // before the first delivery: no reading (NaN)
      rec.tracker = {m.antenna->tracker_error[0], m.antenna->tracker_error[1]};
    }
    rec.theta_meas = a.theta_meas;
    rec.tau_cmd = a.tau_cmd;
    rec.tau_applied = {st.applied_torque[0], st.applied_torque[1]};
    rec.truth_error = truth.pointing_error;
    const Vec3 target(truth.target_boresight[0], truth.target_boresight[1], truth.target_boresight[2]);
    rec.los_error_true = pointing::rotationOnto(target, Vec3(truth.boresight[0], truth.boresight[1], truth.boresight[2]));
    rec.profile = observer.sample(t);
    rec.q_WB_est = a.q_WB_est;
    const double* bq = truth.base_quaternion;
    rec.q_WB_true = Quat(bq[0], bq[1], bq[2], bq[3]);
    rec.attitude_error = pointing::attitudeError(rec.q_WB_true, rec.q_WB_est);
    // What the controller can know: its attitude estimate and the encoders (clearance invisible to
    // them), plus the play's offset when it has the antenna's tracker.
    const Vec2 theta_est = rec.theta_meas + a.antenna_offset;
    const Vec3 bore_est = rec.q_WB_est * pointing::losBoresight(ps.scene.model, theta_est(0), theta_est(1));
    rec.los_error_est = pointing::rotationOnto(target, bore_est.normalized());
    rec.star_outage = a.star_outage;
    if (delivered && a.reading_rejected) ++r.rejected_readings;
    if (const char* bad = nonFinite(rec); *bad) {
      r.ok = false;
      r.stop_status = StepStatus::NonFinite;
      r.error = std::string(describe(StepStatus::NonFinite)) + " of the closed loop: " + bad + " at t = " +
                std::to_string(t) + " s";
      r.t_end = t;
      fig.finish(r);
      return r;
    }
    fig.add(rec, period, a.saturated[0] || a.saturated[1], (st.faults & kTorqueSaturated) != 0, r);
    for (int j = 0; j < 2; ++j)
      if (a.in_play[j] && std::isnan(r.play_onset(j))) r.play_onset(j) = rec.t;
    if (sink) sink(rec);
    r.ticks = k + 1;
    r.t_end = rec.t;
    if (opt.cost) ++opt.cost->ticks;
    if (k == ticks) break;
    if (opt.stop_requested != nullptr && (k + 1) % kStopCheckTicks == 0 && opt.stop_requested()) {
      r.ok = false;
      r.interrupted = true;
      r.error = "interrupted at t = " + formatNumber(t) + " s";
      fig.finish(r);
      return r;
    }
    {
      const CostTimer step(opt.cost, &ClosedLoopCost::step_s);
      tick.advance();
    }
    if (fw.plantFault()) {
      r.ok = false;
      r.stop_status = fw.plantStatus();
      r.error = describeStop(ps.scene.model, fw.plantResult());  // the one message of a stopped step
      r.plant_stop = describePlantStop(ps.scene.model, fw.state().t, fw.plantResult());
      if (k == 0) r.run_reason = "the plant's first step failed: " + r.error;
      fig.finish(r);
      return r;
    }
    // The answer arrives while (lockstep: after) the plant advances and acts
    // from tick k + 1 (the bus).
    if (delivered) {
      const Counters before = fw.counters();
      fw.receive(cmd);
      rejected_in_a_row = fw.counters().rejected > before.rejected ? rejected_in_a_row + 1 : 0;
      if (rejected_in_a_row == 1) rejected_from = before;
    }
    if (rejected_in_a_row >= contract::kRejectedInARow) {  // where the lockstep bench ends the run (exit 3)
      r.ok = false;
      r.rejected_stop = true;
      r.commands_rejected = fw.counters().rejected;
      r.error = "the plant accepted none of the controller's last " + std::to_string(rejected_in_a_row) +
                " commands (" + describe(commonestRejection(rejected_from, fw.counters())) +
                "): stopped at t = " + formatNumber(r.t_end) + " s, as the lockstep bench stops";
      fig.finish(r);
      return r;
    }
  }
  fig.finish(r);
  // A controller none of whose commands the plant took controlled nothing:
  // the run is no result (as on the bench, where it exits 3). (pass 103) Nor one too short for 30 in a row
  // whose plant took fewer than it takes to judge (t = 0's, the 9 after it rejected: it ended "ok").
  const Counters& n = fw.counters();
  r.commands_rejected = n.rejected;
  const long long accepted = n.received - n.rejected;
  if (n.rejected >= contract::kStatusesToJudge && accepted < contract::kStatusesToJudge) {
    r.ok = false;
    r.rejected_stop = true;
    r.error = "the plant accepted " + (accepted == 0 ? std::string("none") : "only " + std::to_string(accepted)) +
              " of the controller's " + std::to_string(n.received) + " commands (" +
              describe(commonestRejection(Counters{}, n)) + ")";
  }
  return r;
}

}  // namespace

std::string controlPeriodProblem(const PlantScene& ps, double control_period) {
  Config fc;
  fc.control_period = control_period;
  const ConfigCheck chk = checkConfig(ps.scene, fc);
  return chk.ok() ? std::string() : "control.period: " + chk.message;
}

ClosedLoopResult runClosedLoop(const PlantScene& ps, contract::ControllerPort& controller,
                               const pointing::TargetProfile& profile, const ClosedLoopOptions& opt,
                               const std::function<void(const TickRecord&)>& sink) {
  Config fc;
  fc.control_period = controller.period();
  if (std::string why = controlPeriodProblem(ps, fc.control_period); !why.empty()) {
    ClosedLoopResult r;
    r.ok = false;
    r.error = std::move(why);
    markUnreached(profile, ps.scene.model, r);  // nothing ran: no figure has a value
    return r;
  }
  return dispatchVariant(ps.scene.model,
                         [&](auto tag) { return run<decltype(tag)>(ps, controller, profile, fc, opt, sink); });
}

}  // namespace gimbalsim::firmware
