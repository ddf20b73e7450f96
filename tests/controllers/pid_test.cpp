// The PID law on its own: signs, feed-forward, limits, anti-windup modes, the
// differenced-rate filter. Expected values are computed here by hand from the
// law in pid.hpp, not by the code under test.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "gimbalsim/controllers/pid.hpp"

namespace gimbalsim::controllers {
namespace {

/// A profile that holds `q` for ever (the slew starts after the test ends).
ControllerConfig holdAt(const Vec2& q) {
  ControllerConfig c;
  c.pointing_mode = PointingMode::Joint;  // the joint law alone (inertial mode: inertial_pointing_test)
  // The plain PID with a constant-inertia feed-forward (the defaults are the default controller's).
  c.approach_margin = 0.0;
  c.gimbal.azimuth_inertia_cos2 = 0.0;
  c.accel_feedforward = AccelFeedForward::Profile;
  c.feedforward_lead = 0.0;
  c.profile.start = q;
  c.profile.slew_start = 1e9;
  for (auto& g : c.axis) g = AxisGains{.kp = 100.0, .ki = 10.0, .kd = 5.0, .inertia = 2.0, .torque_limit = 1e6};
  return c;
}

TEST(Pid, ProportionalAndDerivativeTermsPushTowardTheTarget) {
  ControllerConfig c = holdAt({0.1, -0.2});
  c.axis[0].ki = c.axis[1].ki = 0.0;
  ControllerState s;
  Measurement m;
  m.theta = {0.0, 0.0};
  m.dtheta = {0.5, -1.0};
  const ControlOutput out = update(c, s, m);
  // tau = kp e - kd w (reference at rest, no feed-forward while holding).
  EXPECT_DOUBLE_EQ(out.tau(0), 100.0 * 0.1 - 5.0 * 0.5);
  EXPECT_DOUBLE_EQ(out.tau(1), 100.0 * -0.2 - 5.0 * -1.0);
  EXPECT_DOUBLE_EQ(out.error(0), 0.1);
}

TEST(Pid, ANanCommandIsNotCountedAtTheTorqueLimit) {
  ControllerConfig c = holdAt({0.1, -0.2});
  c.axis[0].kp = std::numeric_limits<double>::quiet_NaN();  // no key gives one: the law's own guard
  ControllerState s;
  Measurement m;
  m.theta = {0.0, 0.0};
  const ControlOutput out = update(c, s, m);
  EXPECT_TRUE(std::isnan(out.tau(0)));
  EXPECT_FALSE(out.saturated[0]);  // was counted "at its own torque limit" while no answer went out
  EXPECT_FALSE(out.saturated[1]);
}

TEST(Pid, FeedForwardOfRateAndAccelerationDuringTheSlew) {
  ControllerConfig c = holdAt({0.0, 0.0});
  c.profile.slew_start = 0.0;
  c.profile.slew_target = {1.0, 2.0};
  c.profile.slew_time = 1.0;
  c.axis[0].kp = c.axis[1].kp = 0.0;
  c.axis[0].ki = c.axis[1].ki = 0.0;
  ControllerState s;
  Measurement m;
  m.t = 0.25;  // u = 1/4
  // Minimum jerk at u: rate 30 u^2 (1-u)^2 d/T, acceleration 60 u (1-u)(1-2u) d/T^2.
  const double rate = 30 * 0.0625 * 0.5625, acc = 60 * 0.25 * 0.75 * 0.5;
  m.dtheta = {rate, 2 * rate};  // on the reference rate: no derivative action
  const ControlOutput out = update(c, s, m);
  EXPECT_NEAR(out.tau(0), 2.0 * acc, 1e-12);
  EXPECT_NEAR(out.tau(1), 2.0 * 2 * acc, 1e-12);
}

TEST(Pid, TorqueNeverExceedsTheLimit) {
  ControllerConfig c = holdAt({5.0, -5.0});
  c.axis[0].torque_limit = 3.0;
  c.axis[1].torque_limit = 7.0;
  ControllerState s;
  for (int k = 0; k < 1000; ++k) {
    Measurement m;
    m.t = k * c.period;
    const ControlOutput out = update(c, s, m);
    ASSERT_EQ(out.tau(0), 3.0);
    ASSERT_EQ(out.tau(1), -7.0);
    ASSERT_TRUE(out.saturated[0] && out.saturated[1]);
    ASSERT_LE(std::abs(s.integral(0)), 3.0);
  }
}

TEST(Pid, IntegralAccumulatesKiErrorTimesPeriod) {
  ControllerConfig c = holdAt({0.01, 0.0});
  c.anti_windup = AntiWindup::None;
  ControllerState s;
  Measurement m;
  for (int k = 0; k < 100; ++k) update(c, s, m);
  EXPECT_NEAR(s.integral(0), 100 * 1e-3 * 10.0 * 0.01, 1e-15);
  EXPECT_EQ(s.integral(1), 0.0);
}

TEST(Pid, ClampingStopsTheIntegralWhileSaturatedOnly) {
  ControllerConfig c = holdAt({1.0, 0.0});
  c.anti_windup = AntiWindup::Clamping;
  c.axis[0].torque_limit = 50.0;  // kp e = 100 > 50: saturated
  ControllerState s;
  Measurement m;
  for (int k = 0; k < 100; ++k) update(c, s, m);
  EXPECT_EQ(s.integral(0), 0.0);
  c.anti_windup = AntiWindup::None;
  for (int k = 0; k < 100; ++k) update(c, s, m);
  EXPECT_GT(s.integral(0), 0.0);
}

TEST(Pid, BackCalculationBleedsTheIntegralByTheExcess) {
  ControllerConfig c = holdAt({1.0, 0.0});
  c.anti_windup = AntiWindup::BackCalculation;
  c.axis[0].torque_limit = 50.0;
  c.axis[0].aw_gain = 20.0;
  ControllerState s;
  Measurement m;
  update(c, s, m);
  // First call: I = 0, tau_u = 100, tau = 50: dI = Ts (ki e + k_aw (50 - 100)).
  EXPECT_NEAR(s.integral(0), 1e-3 * (10.0 * 1.0 + 20.0 * (50.0 - 100.0)), 1e-15);
}

TEST(Pid, DifferencedRateConvergesToTheTrueRate) {
  ControllerConfig c = holdAt({0.0, 0.0});
  c.rate_source = RateSource::Difference;
  c.rate_filter_hz = 50.0;
  ControllerState s;
  const double w = 0.3;  // [rad/s]
  ControlOutput out;
  for (int k = 0; k < 200; ++k) {  // 10 filter time constants (3.2 ms each)
    Measurement m;
    m.t = k * c.period;
    m.theta = {w * m.t, -2 * w * m.t};
    m.dtheta = {99.0, 99.0};  // must be ignored
    out = update(c, s, m);
  }
  EXPECT_NEAR(out.rate(0), w, 1e-4 * w);
  EXPECT_NEAR(out.rate(1), -2 * w, 1e-4 * w);
}

TEST(Pid, DifferencedRateIgnoresAGapInsteadOfSpiking) {
  ControllerConfig c = holdAt({0.0, 0.0});
  c.rate_source = RateSource::Difference;
  ControllerState s;
  Measurement m;
  update(c, s, m);
  m.t = 1.0;  // 1000 periods later, 0.5 rad further (a controller joining late)
  m.theta = {0.5, 0.0};
  EXPECT_EQ(update(c, s, m).rate(0), 0.0);  // re-primed, no 500 rad/s spike
  m.t += c.period;
  m.theta(0) += 1e-4;  // then differences resume: 0.1 rad/s, filtered
  const double w = update(c, s, m).rate(0);
  EXPECT_GT(w, 0.0);
  EXPECT_LT(w, 0.1);
}

TEST(Pid, ApproachCapsTheClosingRateAtLargeErrorsOnly) {
  ControllerConfig c = holdAt({0.0, 0.0});
  c.axis[0].ki = c.axis[1].ki = 0.0;
  c.axis[0].torque_limit = c.axis[1].torque_limit = 8.0;
  c.approach_margin = 0.5;  // a = 0.5 * 8 / 2 = 2 rad/s^2; switch at |e| = 2 a (kd/kp)^2 = 0.01 rad
  ControllerState s;
  Measurement m;
  m.theta = {-1.0, -0.005};  // azimuth far (e = 1), elevation near (e = 0.005)
  m.dtheta = {0.5, 0.0};
  const ControlOutput out = update(c, s, m);
  EXPECT_DOUBLE_EQ(out.tau_unsat(0), 5.0 * (std::sqrt(2.0 * 2.0 * 1.0) - 0.5));  // kd (sqrt(2 a e) - w)
  EXPECT_DOUBLE_EQ(out.tau_unsat(1), 100.0 * 0.005);                              // plain kp e
}

TEST(Pid, TriplePoleGains) {
  const AxisGains g = triplePoleGains(10.0, 4.0, 20.0, 5.0);
  // (s + 4)^3 = s^3 + 12 s^2 + 48 s + 64, times J = 10.
  EXPECT_DOUBLE_EQ(g.kd, 120.0);
  EXPECT_DOUBLE_EQ(g.kp, 480.0);
  EXPECT_DOUBLE_EQ(g.ki, 640.0);
  EXPECT_DOUBLE_EQ(g.inertia, 10.0);
}


// A NaN or Inf reading would stay in the integral, the filter and the
// estimate for good: it is rejected (counted, the last command held) and the
// controller goes on exactly as if it had never come.
TEST(Pid, ANonFiniteReadingIsRejectedAndLeavesTheStateAsItWas) {
  ControllerConfig c = holdAt({0.1, -0.2});
  c.rate_source = RateSource::Difference;
  ControllerState clean, hit;
  Measurement m1, m2;
  m1.t = 0.0;
  m1.theta = {0.01, -0.02};
  m2.t = 1e-3;
  m2.theta = {0.02, -0.03};
  m2.dtheta = {0.3, -0.1};
  const ControlOutput first = update(c, clean, m1);
  update(c, hit, m1);
  for (const double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
    Measurement m = m2;
    m.theta(1) = bad;
    const ControlOutput held = update(c, hit, m);
    EXPECT_TRUE(held.rejected);
    EXPECT_EQ(held.tau, first.tau) << "the last command is held";
  }
  Measurement rate_nan = m2;
  rate_nan.dtheta(0) = std::nan("");
  EXPECT_TRUE(update(c, hit, rate_nan).rejected);
  EXPECT_EQ(hit.rejected_readings, 3);
  EXPECT_EQ(clean.rejected_readings, 0);
  const ControlOutput a = update(c, clean, m2), b = update(c, hit, m2);
  EXPECT_FALSE(b.rejected);
  EXPECT_TRUE(b.tau.allFinite());
  EXPECT_EQ(a.tau, b.tau) << "the rejected readings left no trace";
  EXPECT_EQ(clean.integral, hit.integral);
  EXPECT_EQ(clean.rate, hit.rate);
}

}  // namespace
}  // namespace gimbalsim::controllers
