// The backlash guard (play_guard.hpp): it tells the light side of a play
// from the whole chain by the rate change a command makes, steps that axis
// on a rate gain the light side can take from then on, and never acts on a
// rigid chain. docs/MODEL.md "The controller across a play" gives the
// analysis these tests check: with one tick of latency the light side's rate
// error obeys e[k+2] = e[k+1] - g e[k], g = kd Ts / J.
#include <gtest/gtest.h>

#include <cmath>

#include "controllers/closed_loop_util.hpp"
#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/controllers/pid.hpp"
#include "test_util.hpp"

namespace gimbalsim::controllers {
namespace {

constexpr double kTs = 1.0e-3;  // [s]

TEST(PlayGuard, EvidenceIsTheLightSidesRateChange) {
  const double J_play = 0.1, J_chain = 17.6, limit = 50.0, tau = 5.0;  // [kg m^2], [N m]
  EXPECT_TRUE(playEvidence(kTs * tau / J_play, tau, kTs, J_play, limit));     // the light side alone
  EXPECT_TRUE(playEvidence(-kTs * tau / J_play, -tau, kTs, J_play, limit));   // either sign
  EXPECT_FALSE(playEvidence(kTs * tau / J_chain, tau, kTs, J_play, limit));   // the whole chain
  EXPECT_FALSE(playEvidence(-kTs * tau / J_play, tau, kTs, J_play, limit));   // an impact stops it: not the play
  EXPECT_FALSE(playEvidence(1.0, 0.4, kTs, J_play, limit));                   // below 1 % of the limit: no evidence
  // More than twice the light side's change is not the command's (an impact's friction kick):
  // measured on paper_clearance after an elevation motor failure, 4.8 times it.
  EXPECT_TRUE(playEvidence(1.9 * kTs * tau / J_play, tau, kTs, J_play, limit));
  EXPECT_FALSE(playEvidence(4.8 * kTs * tau / J_play, tau, kTs, J_play, limit));
}

/// The light side of a play alone: a free inertia J under the law, the
/// command acting one tick after it is computed (the bus's latency), as in
/// the plant. Returns the largest |rate| [rad/s] over the last 100 of n ticks.
double lightSide(const ControllerConfig& c, double J, int n, bool* engaged) {
  ControllerState s;
  double theta = 0.0, rate = 1.0e-3, tau_acting = 0.0, largest = 0.0;  // a small push [rad/s]
  for (int k = 0; k < n; ++k) {
    Measurement m;
    m.t = k * kTs;  // before the slew: the reference holds still
    m.theta = Vec2(theta, 0.0);
    m.dtheta = Vec2(rate, 0.0);
    const ControlOutput out = update(c, s, m);
    rate += kTs * tau_acting / J;
    theta += kTs * rate;
    tau_acting = out.tau(0);
    if (k >= n - 100) largest = std::max(largest, std::fabs(rate));
    *engaged = out.in_play[0];
  }
  return largest;
}

TEST(PlayGuard, TheLightSideIsUnstableUnderTheChainsGainAndStableUnderTheGuards) {
  // Joint pointing, profile feed-forward: nothing but the PID acts at rest.
  const std::vector<std::string> sets = {"pointing.mode=joint", "pointing.accel_feedforward=profile"};
  ControllerConfig guarded = loadControllerConfig(test::defaultControllerConfig(), sets);
  ControllerConfig unguarded = guarded;
  unguarded.axis[0].play_inertia = 0.0;
  const double J_light = 0.1;  // shaft 1 about the azimuth axis [kg m^2]: g = 1056 * 1e-3 / 0.1 = 10.6
  bool engaged = false;
  const double free_rate = lightSide(unguarded, J_light, 400, &engaged);
  EXPECT_FALSE(engaged);
  EXPECT_GT(free_rate, 0.1) << "kd Ts / J = 10.6: the push should grow a hundredfold, to the torque limit";
  const double guarded_rate = lightSide(guarded, J_light, 400, &engaged);
  EXPECT_TRUE(engaged);
  EXPECT_LT(guarded_rate, 1.0e-4) << "the guard's g = 0.25 (no antenna sensor) should damp the push out";
  // The whole chain under the same law: the guard sees no play and stays off.
  lightSide(guarded, 17.6, 400, &engaged);
  EXPECT_FALSE(engaged);
}

ClosedLoopResult track(const Scene& sc, const ControllerConfig& c, double tracking = 5.0) {
  ClosedLoopOptions opt;
  opt.duration = c.profile.trackStart() + tracking;  // 5 s: the pointing study's 8.5 s
  return runClosedLoop(sc, c, opt);
}

/// Tracking ticks with a command at the controller's limit, and the run.
ClosedLoopResult trackCounting(const Scene& sc, const ControllerConfig& c, long long* limited_track) {
  ClosedLoopOptions opt;
  opt.duration = c.profile.trackStart() + 5.0;  // the pointing study's 8.5 s
  *limited_track = 0;
  return runClosedLoop(sc, c, opt, [&](const TickRecord& t) {
    const bool limited = t.tau_cmd.cwiseAbs().maxCoeff() >= c.axis[0].torque_limit;
    if (t.ref.segment == pointing::Segment::Track && limited) ++*limited_track;
  });
}

TEST(PlayGuard, EveryTiltingJournalNoLimitCycleAndWithinThePlayOnEncodersAlone) {
  // paper_spatial2 at c = 0.1 mm: without the guard the azimuth command sat
  // at its limit in 7777 of 8501 ticks and the RMS while tracking was 6.3e-3 rad.
  // paper_both_spatial at 0.8 mm: 3.3e-2 rad at the guard's former in-play
  // rate gain (0.5 instead of 0.375 without the antenna's sensors), beyond 2c/L.
  const double L = 0.05;  // bearing length of every tilting journal [m]
  const long long tracking_ticks = 5001;
  const ControllerConfig c = loadControllerConfig(test::defaultControllerConfig());
  for (const char* name : {"paper_spatial2", "paper_spatial1", "paper_both_spatial"}) {
    for (const double c_m : {1.0e-4, 8.0e-4}) {
      long long limited_track = 0;
      const ClosedLoopResult r = trackCounting(
          test::scene(name, {"contact.clearance=" + std::to_string(c_m)}), c, &limited_track);
      ASSERT_TRUE(r.ok) << name << " " << c_m << ": " << r.error;
      EXPECT_LE(limited_track, tracking_ticks / 100) << name << " " << c_m << ": at most 1 % of tracking at the limit";
      EXPECT_LE(r.rms_truth_error_track, 2.0 * c_m / L) << name << " " << c_m << ": encoders only, within 2c/L";
      EXPECT_GT(r.rms_truth_error_track, 0.0) << name << " " << c_m;
    }
  }
}

TEST(PlayGuard, RigidChainsRunBitForBitAsWithoutTheGuard) {
  const ControllerConfig guarded = loadControllerConfig(test::defaultControllerConfig());
  ControllerConfig unguarded = guarded;
  for (auto& g : unguarded.axis) g.play_inertia = 0.0;
  for (const char* name : {"paper_ideal", "paper_clearance"}) {
    const Scene sc = test::scene(name);
    const ClosedLoopResult a = track(sc, guarded, 1.0), b = track(sc, unguarded, 1.0);  // slew, hold, 1 s tracking
    ASSERT_TRUE(a.ok && b.ok) << name;
    EXPECT_EQ(a.rms_truth_error_track, b.rms_truth_error_track) << name;
    EXPECT_EQ(a.max_truth_error_track, b.max_truth_error_track) << name;
  }
}

}  // namespace
}  // namespace gimbalsim::controllers
