// The joint reference of the pointing law (pid.hpp): the attitude estimator's
// step each period, then, in inertial mode, the inverse kinematics of the
// inertial target seen from the estimated base.
//
// Per period, at t = seq Ts, with the gyro sample w_k (held when missing):
//   estimator: propagate to t on (w_{k-1} + w_k) / 2 (trapezoid: second
//              order), then omega_B = w_k - bias; correct with a new star
//              sample (its own stamp t_s, possibly late) (attitude_estimator.hpp)
//   target:    profile: d_W = b(q_p), dd_W = J(q_p) dq_p (b, J: boresight and
//              its Jacobian at the initial base pose, the truth's losBoresight
//              with the configured gimbal.* geometry); fixed: d_W = the
//              configured direction, dd_W = 0
//   in base:   d_B = R^T d_W, d_B_dot = R^T dd_W - omega_B x d_B  (R = R(q_WB_est))
//   joints:    q_ref = solveAngles(d_B, previous q_ref), dq_ref = solveRates(q_ref, d_B_dot),
//   feed-forward acceleration a (pointing.accel_feedforward):
//     profile:  a = ddq_ref = ddq_p (the profile's acceleration; the base's
//               reaction and the IK's curvature are left to the feedback)
//     inertial: ddq_ref = solveAccelerations(q_ref, dq_ref, d_B_ddot), with
//               ddd_W = J(q_p) ddq_p + curvature(q_p, dq_p) and alpha_B the
//               base's angular acceleration (the gyro's rate differenced over
//               the period, low-passed); a = each shaft's inertial angular
//               acceleration about its joint (J_i a_i is the torque that gives it):
//                 a1 = ddq1 + k1.alpha_B
//                 a2 = ddq2 + k2.alpha_B + dq1 k2.(omega_B x k1)   (k2 = R1(q1) k2_S1)
//     model:    ddq_ref and the torque from the free-floating plant model, the
//               base's reaction predicted, not measured (model_feedforward.hpp)
#include <cmath>

#include "gimbalsim/controllers/gimbal_ik.hpp"
#include "gimbalsim/controllers/model_feedforward.hpp"
#include "gimbalsim/controllers/pid.hpp"

namespace gimbalsim::controllers {

void jointReference(const ControllerConfig& c, ControllerState& s, const Measurement& meas,
                    ControlOutput& out) noexcept {
  out.profile = c.profile.at(meas.t);
  const AttitudeMeasurement& att = meas.att;

  // Attitude estimate at meas.t.
  AttitudeEstimatorState& e = s.estimator;
  const Vec3 gyro = att.gyro_valid || !s.ref_primed ? att.gyro : s.gyro_prev;
  if (!att.gyro_valid) ++s.gyro_missing;
  if (!s.ref_primed) {
    e.t = meas.t;  // a controller joining late starts its estimate now
  } else {
    propagate(c.estimator, e, meas.t, 0.5 * (s.gyro_prev + gyro));
  }
  propagate(c.estimator, e, meas.t, gyro);  // no time step: omega_B = gyro - bias
  s.gyro_prev = gyro;
  if (att.star_valid && !att.star_outage) correct(c.estimator, e, att.star_time, att.star_q);
  out.star_outage = att.star_outage;
  if (att.star_outage) ++s.star_outage_periods;
  out.q_WB_est = e.q_WB;
  out.omega_B_est = e.omega_B;
  // The base's angular acceleration: the corrected rate differenced over the period, low-passed.
  const double dt = meas.t - s.t_alpha_prev;
  if (s.ref_primed && dt > 0.0 && dt <= 10.0 * c.period) {
    const double k = dt / (dt + 1.0 / (2.0 * M_PI * c.base_accel_filter_hz));
    s.alpha_B += k * ((e.omega_B - s.omega_B_prev) / dt - s.alpha_B);
  } else {
    s.alpha_B.setZero();
  }
  s.omega_B_prev = e.omega_B;
  s.t_alpha_prev = meas.t;

  const Vec2& ddq_p = out.profile.ddq;
  if (c.pointing_mode == PointingMode::Joint) {
    out.ref = out.profile;
    out.accel_ff = ddq_p;
    if (c.accel_feedforward == AccelFeedForward::Model) {
      const ReducedDynamics r = reducedDynamics(c.plant_model, out.ref.q, out.ref.dq, e.omega_B);
      out.tau_ff = r.H * ddq_p + r.c;
    }
    s.ref_primed = true;
    return;
  }

  const GimbalGeometry g = gimbalGeometry(c.gimbal.joint1_axis, c.gimbal.joint2_axis, c.gimbal.boresight);
  Vec3 d_W, dd_W, ddd_W;
  if (c.target == PointingTarget::Fixed) {
    d_W = c.fixed_direction.normalized();
    dd_W.setZero();
    ddd_W.setZero();
  } else {
    d_W = boresightB(g, out.profile.q);
    const Mat32 J_p = boresightJacobian(g, out.profile.q);
    dd_W = J_p * out.profile.dq;
    ddd_W = J_p * ddq_p + boresightCurvature(g, out.profile.q, out.profile.dq);
  }
  const LosInBase los = losInBase(d_W, dd_W, ddd_W, e.q_WB.toRotationMatrix(), e.omega_B, s.alpha_B);
  const Vec2 prev = s.ref_primed ? s.ref_prev : (c.target == PointingTarget::Profile ? out.profile.q : meas.theta);
  const IkSolution sol = solveAngles(g, los.d_B, prev);
  out.ref.q = sol.theta;
  out.ref.dq = solveRates(g, sol.theta, los.d_B_dot);
  if (c.accel_feedforward == AccelFeedForward::Model) {
    const ReducedDynamics r = reducedDynamics(c.plant_model, sol.theta, out.ref.dq, e.omega_B);
    const LosInBase los0 = losInBase(d_W, dd_W, ddd_W, e.q_WB.toRotationMatrix(), e.omega_B, Vec3::Zero());
    out.ref.ddq = pointingAccelerations(g, r, sol.theta, out.ref.dq, los0.d_B, los0.d_B_ddot);
    out.accel_ff = out.ref.ddq;
    out.tau_ff = r.H * out.ref.ddq + r.c;
  } else if (c.accel_feedforward == AccelFeedForward::Inertial) {
    out.ref.ddq = solveAccelerations(g, sol.theta, out.ref.dq, los.d_B_ddot);
    const Vec3 k2 = axisAngle(g.k1_B, sol.theta(0)) * g.k2_S1;
    out.accel_ff(0) = out.ref.ddq(0) + g.k1_B.dot(s.alpha_B);
    out.accel_ff(1) = out.ref.ddq(1) + k2.dot(s.alpha_B) + out.ref.dq(0) * k2.dot(e.omega_B.cross(g.k1_B));
  } else {
    out.ref.ddq = c.target == PointingTarget::Profile ? ddq_p : Vec2::Zero();
    out.accel_ff = out.ref.ddq;
  }
  out.ref.segment = out.profile.segment;
  out.ik_singular = sol.singular;
  s.ref_prev = sol.theta;
  s.ref_primed = true;
}

}  // namespace gimbalsim::controllers
