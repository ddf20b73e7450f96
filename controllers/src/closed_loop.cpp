#include "gimbalsim/controllers/closed_loop.hpp"

#include <algorithm>
#include <cmath>

#include "gimbalsim/dynamics/simulate.hpp"

namespace gimbalsim::controllers {
namespace {

template <class V>
ClosedLoopResult run(const Model& m, const ControllerConfig& c, const ClosedLoopOptions& opt,
                     const std::function<void(const TickRecord&)>& sink) {
  ClosedLoopResult r;
  Data<V> d(m);
  State<V> s = initialState<V>(m);
  ControllerState cs;
  const long long steps_per_tick = std::max(1LL, std::llround(c.period / m.integrator.step));
  const long long ticks = std::llround(opt.duration / c.period);
  const TargetProfile& p = c.profile;
  Vec2 tau_pending = Vec2::Zero();  // on the bus
  double sum_sq = 0.0;
  long long n_track = 0;
  double last_unsettled = p.slewEnd();  // last hold time with the error outside the band
  bool hold_seen = false;
  for (long long k = 0; k <= ticks; ++k) {
    const double t = static_cast<double>(k) * c.period;
    TickRecord rec;
    rec.t = t;
    rec.theta_true = {s.theta(0), s.theta(1)};
    Measurement meas;
    meas.t = t;
    for (int i = 0; i < 2; ++i) meas.theta(i) = quantize(rec.theta_true(i), m.sensors.encoder_resolution);
    meas.dtheta = {s.dtheta(0), s.dtheta(1)};
    const ControlOutput out = update(c, cs, meas);
    rec.ref = out.ref;
    rec.theta_meas = meas.theta;
    rec.tau_cmd = out.tau;
    const Vec2 cmd = opt.one_tick_delay ? tau_pending : out.tau;
    tau_pending = out.tau;
    Input u;
    for (int i = 0; i < 2; ++i) u.tau(i) = std::clamp(cmd(i), -m.torque_limit(i), m.torque_limit(i));
    rec.tau_applied = u.tau;

    kinematics(m, d, s.q, s.v);
    rec.truth_error = pointingError(boresight(m, d, s), losBoresight(m, out.ref.q(0), out.ref.q(1)));
    const double ej = (out.ref.q - rec.theta_true).cwiseAbs().maxCoeff();
    switch (out.ref.segment) {
      case Segment::Wait: break;
      case Segment::Slew: r.max_joint_error_slew = std::max(r.max_joint_error_slew, ej); break;
      case Segment::Hold:
        hold_seen = true;
        r.max_joint_error_hold = std::max(r.max_joint_error_hold, ej);
        if (ej >= opt.settle_tol) last_unsettled = t + c.period;
        r.max_truth_error_hold_end = rec.truth_error;
        break;
      case Segment::Track:
        r.max_joint_error_track = std::max(r.max_joint_error_track, ej);
        r.max_truth_error_track = std::max(r.max_truth_error_track, rec.truth_error);
        sum_sq += rec.truth_error * rec.truth_error;
        ++n_track;
        break;
    }
    r.max_abs_tau = r.max_abs_tau.cwiseMax(u.tau.cwiseAbs());
    if (out.saturated[0] || out.saturated[1]) ++r.saturated_ticks;
    if (sink) sink(rec);
    r.ticks = k + 1;
    r.t_end = t;
    if (k == ticks) break;
    for (long long j = 0; j < steps_per_tick; ++j) {
      const StepStatus st = step(m, d, s, u);
      if (st != StepStatus::Ok) {
        r.ok = false;
        r.error = std::string(describe(st)) + " at t = " + std::to_string(d.fail_time) + " s";
        return r;
      }
    }
  }
  if (hold_seen && last_unsettled < p.trackStart()) r.settle_time = last_unsettled - p.slewEnd();
  if (n_track > 0) r.rms_truth_error_track = std::sqrt(sum_sq / static_cast<double>(n_track));
  return r;
}

}  // namespace

ClosedLoopResult runClosedLoop(const Model& m, const ControllerConfig& c, const ClosedLoopOptions& opt,
                               const std::function<void(const TickRecord&)>& sink) {
  return dispatchVariant(m, [&](auto tag) { return run<decltype(tag)>(m, c, opt, sink); });
}

}  // namespace gimbalsim::controllers
