#include "gimbalsim/controllers/pid.hpp"

#include <algorithm>
#include <cmath>

namespace gimbalsim::controllers {

namespace {

bool finite2(const Vec2& v) noexcept { return std::isfinite(v(0)) && std::isfinite(v(1)); }

/// The answer to a rejected reading: the last command, the reference the
/// controller last tracked (inertial: the last IK solution), state untouched.
ControlOutput held(const ControllerConfig& c, const ControllerState& s, double t) noexcept {
  ControlOutput out;
  out.rejected = true;
  out.tau = s.last_tau;
  out.tau_unsat = s.last_tau;
  if (std::isfinite(t)) out.profile = c.profile.at(t);
  out.ref = out.profile;
  if (c.pointing_mode == PointingMode::Inertial && s.ref_primed) out.ref.q = s.ref_prev;
  out.q_WB_est = s.estimator.q_WB;
  out.omega_B_est = s.estimator.omega_B;
  return out;
}

}  // namespace

ControlOutput update(const ControllerConfig& c, ControllerState& s, const Measurement& reading) noexcept {
  // A NaN or Inf would stay in the integral, the filter and the estimate for
  // good: reject it before it touches the state.
  if (!std::isfinite(reading.t) || !finite2(reading.theta) || !finite2(reading.dtheta)) {
    ++s.rejected_readings;
    return held(c, s, reading.t);
  }
  Measurement meas = reading;
  AttitudeMeasurement& att = meas.att;
  if (att.gyro_valid && !att.gyro.allFinite()) {
    att.gyro_valid = false;  // held as a missing gyro sample
    ++s.rejected_readings;
  }
  if (att.star_valid && (!std::isfinite(att.star_time) || !att.star_q.coeffs().allFinite())) {
    att.star_valid = false;
    ++s.rejected_readings;
  }
  ControlOutput out;
  jointReference(c, s, meas, out);  // inertial_reference.cpp
  const double Ts = c.period;
  // First-order low-pass of the backward difference: alpha = Ts / (Ts + 1/(2 pi fc)).
  // The difference uses the real spacing of the samples; a gap (missed
  // statuses, a controller joining late) of more than 10 periods or a time
  // going backwards re-primes instead of producing a spike.
  // Feed-forward torque: model: the computed torque of the free-floating
  // plant (inertial_reference.cpp filled out.tau_ff); otherwise the gimbal's
  // own dynamics (fixed-base Lagrangian of M = diag(J1(theta2), J2), at the
  // reference): J1(theta2) = J1_0 + C (cos 2 theta2 - 1),
  //   tau1 = J1(theta2) a1 + J1'(theta2) w1 w2,   tau2 = J2 a2 - J1'(theta2) w1^2 / 2.
  if (c.accel_feedforward != AccelFeedForward::Model) {
    const double C = c.gimbal.azimuth_inertia_cos2, th2 = out.ref.q(1);
    const double dJ1 = -2.0 * C * std::sin(2.0 * th2);
    const double w1 = out.ref.dq(0), w2 = out.ref.dq(1);
    out.tau_ff = {(c.axis[0].inertia + C * (std::cos(2.0 * th2) - 1.0)) * out.accel_ff(0) + dJ1 * w1 * w2,
                  c.axis[1].inertia * out.accel_ff(1) - 0.5 * dJ1 * w1 * w1};
  }
  const double dt = meas.t - s.t_prev;
  const bool difference_ok = s.primed && dt > 0.0 && dt <= 10.0 * Ts;
  const double alpha = dt / (dt + 1.0 / (2.0 * M_PI * c.rate_filter_hz));
  // The command computed now acts over the next period: the feed-forward
  // extrapolated by its backward difference to feedforward_lead ahead.
  const Vec2 tau_ff = difference_ok ? Vec2(out.tau_ff + (c.feedforward_lead / dt) * (out.tau_ff - s.tau_ff_prev))
                                    : out.tau_ff;
  // The antenna's own sensors (tracker_fusion.hpp): the play's offset from
  // the tracker (zero without one) and the antenna's rate from its gyro.
  const Vec3 k1 = c.gimbal.joint1_axis.normalized(), k2 = c.gimbal.joint2_axis.normalized();
  const Vec3 bs = c.gimbal.boresight.normalized();
  // The status's tick (a hostile seq can make it huge: beyond 1e15 none, the tracker then unused).
  const double tick_real = meas.t / Ts;
  const std::int64_t tick = tick_real >= 0.0 && tick_real <= 1e15 ? std::llround(tick_real) : -1;
  out.load_offset = loadOffset(c.antenna, k1, k2, bs, s.fusion, tick, Ts, out.ref.q - meas.theta, meas.theta(1));
  Vec2 w_load = Vec2::Zero();
  const bool have_load_rate = loadRate(c.antenna, k1, k2, bs, s.fusion, tick, meas.theta, out.omega_B_est, w_load);
  const double kappa_play = antennaHeard(c.antenna, s.fusion) ? kPlayRateGain : kPlayRateGainEncoders;
  for (int i = 0; i < 2; ++i) {
    const AxisGains& g = c.axis[i];
    double w = meas.dtheta(i);
    if (c.rate_source == RateSource::Difference) {
      if (difference_ok) s.rate(i) += alpha * ((meas.theta(i) - s.theta_prev(i)) / dt - s.rate(i));
      w = s.rate(i);
    }
    // Backlash guard (play_guard.hpp): once the play is seen, gains the light side can take.
    if (g.play_inertia > 0.0 && !s.play.seen[i] && difference_ok && s.play.primed >= 2 &&
        playEvidence(w - s.play.rate_prev(i), s.play.tau_prev2(i), Ts, g.play_inertia, g.torque_limit))
      s.play.seen[i] = true;
    const bool in_play = s.play.seen[i];
    // A suspect encoder (fault_monitor.hpp): no position feedback on this axis, only the rate's.
    const bool suspect = s.monitor.suspect[i];
    // On the antenna's sensors (tracker_fusion.hpp, docs/MODEL.md 11.7): the
    // error and the chain's rate are the antenna's, on a triple pole at
    // antenna.bandwidth over the axis's inertia, and the motor is damped
    // against the antenna (antenna.motor_damping) so that inside the play it
    // follows the antenna instead of crossing at the torque limit.
    const bool at_antenna = have_load_rate && !suspect && g.inertia > 0.0;
    const bool play_gains = at_antenna && in_play;
    const double wa = c.antenna.bandwidth;
    const double kp = play_gains ? 3.0 * g.inertia * wa * wa : g.kp;
    const double ki = play_gains ? g.inertia * wa * wa * wa : g.ki;
    const double kd = play_gains ? 3.0 * g.inertia * wa
                      : in_play && !at_antenna ? std::min(g.kd, kappa_play * g.play_inertia / Ts) : g.kd;
    const double w_chain = at_antenna ? w_load(i) : w;
    const double tau_motor = at_antenna ? c.antenna.motor_damping * (w_load(i) - w) : 0.0;
    const double e = out.ref.q(i) - meas.theta(i) - out.load_offset(i);
    // Large-error approach (proximate time-optimal servo): the PD asks for a
    // closing rate (kp/kd) e; above sqrt(2 a |e|), with a the deceleration the
    // motor can give (approach_margin * limit / J), it could not stop in time
    // and would overshoot into a limit cycle, so the closing rate is capped
    // there. Below |e| = 2 a (kd/kp)^2 this is the plain PD, bit for bit.
    bool approach = false;
    double tau_pd = (suspect ? 0.0 : kp * e) + kd * (out.ref.dq(i) - w_chain);
    if (!suspect && c.approach_margin > 0.0 && g.inertia > 0.0 && kd > 0.0) {
      const double v_max = std::sqrt(2.0 * c.approach_margin * g.torque_limit / g.inertia * std::fabs(e));
      if (kp * std::fabs(e) > kd * v_max) {
        approach = true;
        tau_pd = kd * (out.ref.dq(i) + std::copysign(v_max, e) - w_chain);
      }
    }
    const double tau_u = tau_ff(i) + tau_pd + tau_motor + s.integral(i);
    const double tau = std::clamp(tau_u, -g.torque_limit, g.torque_limit);
    const bool sat = tau != tau_u && !std::isnan(tau_u);  // NaN is no command at a limit (it is never sent)
    double dI = approach || suspect ? 0.0 : Ts * ki * e;  // integrate in the linear region only
    // Nor while the motor moves against the antenna: inside the play the
    // antenna's error is out of the motor's reach and would wind the integral.
    // Then no back-calculation either (alone it wound the integral against a
    // saturated command), and the integral decays: with both journals tilting
    // the two never move together, and a held integral held its error for
    // the run (paper_both_spatial: -30 N m, 4e-3 rad; docs/MODEL.md 11.7).
    const bool disengaged = at_antenna && std::fabs(w_load(i) - w) > c.antenna.engaged_rate;
    const double leak = c.antenna.integral_leak_time > 0.0 ? std::min(1.0, Ts / c.antenna.integral_leak_time) : 0.0;
    if (disengaged) dI = -leak * s.integral(i);  // at most the whole integral a tick, never past 0
    switch (c.anti_windup) {
      case AntiWindup::None: break;
      case AntiWindup::Clamping:
        if (sat && dI * tau_u > 0.0) dI = 0.0;  // would push further into the limit
        break;
      case AntiWindup::BackCalculation:
        if (!disengaged) dI += Ts * g.aw_gain * (tau - tau_u);
        break;
    }
    s.integral(i) += dI;
    if (c.anti_windup != AntiWindup::None) s.integral(i) = std::clamp(s.integral(i), -g.torque_limit, g.torque_limit);
    out.tau(i) = tau;
    out.tau_unsat(i) = tau_u;
    out.error(i) = e;
    out.rate(i) = w;
    out.saturated[i] = sat;
    out.in_play[i] = in_play;
    s.play.rate_prev(i) = w;
  }
  s.play.tau_prev2 = s.play.tau_prev;
  s.play.tau_prev = out.tau;
  s.play.primed = std::min(s.play.primed + 1, 2);
  s.theta_prev = meas.theta;
  s.t_prev = meas.t;
  s.primed = true;
  s.last_tau = out.tau;
  s.tau_ff_prev = out.tau_ff;
  return out;
}

AxisGains triplePoleGains(double J, double omega, double torque_limit, double aw_gain) {
  AxisGains g;
  g.kd = 3.0 * J * omega;
  g.kp = 3.0 * J * omega * omega;
  g.ki = J * omega * omega * omega;
  g.inertia = J;
  g.torque_limit = torque_limit;
  g.aw_gain = aw_gain;
  return g;
}

}  // namespace gimbalsim::controllers
