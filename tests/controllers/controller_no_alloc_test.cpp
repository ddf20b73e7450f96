// update() makes no heap allocation and throws nothing: a counting global
// operator new, and Eigen's malloc guard in the checked build.
#include <gtest/gtest.h>

#include <cmath>
#include <type_traits>

#include "alloc_guard.hpp"
#include "controllers/closed_loop_util.hpp"
#include "gimbalsim/controllers/config.hpp"

namespace gimbalsim::controllers {
namespace {

static_assert(noexcept(update(std::declval<const ControllerConfig&>(), std::declval<ControllerState&>(),
                              std::declval<const Measurement&>())));
static_assert(noexcept(std::declval<const TargetProfile&>().at(0.0)));

TEST(ControllerNoAlloc, TheCounterSeesAllocations) {
  EXPECT_GE(test::probeAllocations(), 1);
}

TEST(ControllerNoAlloc, UpdateAllocatesNothingInAnySegmentOrMode) {
  // Every rate source, anti-windup and pointing mode, with the attitude
  // estimator fed gyro and (late) star samples, an outage and missing gyro samples.
  const ControllerConfig base = loadControllerConfig(std::string(GIMBALSIM_CONTROLLER_CONFIG_DIR) + "/default.yaml");
  for (int variant = 0; variant < 4; ++variant)
  for (auto rs : {RateSource::Status, RateSource::Difference}) {
    for (auto aw : {AntiWindup::None, AntiWindup::Clamping, AntiWindup::BackCalculation}) {
      ControllerConfig c = base;
      c.rate_source = rs;
      c.anti_windup = aw;
      // inertial (profile target), inertial with a tilted elevation axis (Gauss-Newton IK),
      // inertial with a fixed target, joint
      c.pointing_mode = variant == 3 ? PointingMode::Joint : PointingMode::Inertial;
      if (variant == 1) c.gimbal.joint2_axis = Vec3(0.0, 1.0, 0.1);
      if (variant == 2) c.target = PointingTarget::Fixed;
      ControllerState s;
      const long long before = test::g_allocations.load();
      test::setEigenMallocAllowed(false);
      double sink = 0.0;
      for (int k = 0; k < 10000; ++k) {  // 10 s: wait, slew, hold and track
        Measurement m;
        m.t = k * c.period;
        m.theta = {0.001 * k * c.period, 0.0};
        // The attitude sensors: a turning base, a star sample every 100 ms
        // (20 ms late), an outage over 6..7 s, the gyro missing every 50th period.
        const double t = m.t;
        m.att.gyro = {1e-3, -2e-3, 5e-3};
        m.att.gyro_valid = k % 50 != 7;
        m.att.star_outage = t >= 6.0 && t <= 7.0;
        m.att.star_valid = k % 100 == 20 && !m.att.star_outage;
        m.att.star_time = t - 0.02;
        m.att.star_q = expRotation(Vec3(1e-3, -2e-3, 5e-3) * m.att.star_time);
        // Rejected readings (a NaN angle, an Inf gyro sample) take their own path: no allocation there either.
        if (k % 997 == 5) m.theta(1) = std::nan("");
        if (k % 991 == 3) m.att.gyro(0) = HUGE_VAL;
        sink += update(c, s, m).tau.sum();
      }
      test::setEigenMallocAllowed(true);
      EXPECT_EQ(test::g_allocations.load() - before, 0);
      EXPECT_TRUE(std::isfinite(sink));
      EXPECT_GT(s.estimator.samples_used, 50);
      EXPECT_EQ(s.star_outage_periods, 1001 - 1);  // less the rejected reading at k = 6984 (kept no state)
      EXPECT_EQ(s.rejected_readings, 11 + 11);  // k = 5 + 997 j and 3 + 991 j below 10000, j = 0..10
    }
  }
}

TEST(ControllerNoAlloc, AnswerStatusWithItsFaultMonitorAllocatesNothing) {
  // The controller's side of a tick as the bench runs it (answerStatus):
  // stale statuses (held, then safe), a stuck azimuth encoder (suspect: rate
  // feedback only), attitudes noted without a status.
  static_assert(noexcept(answerStatus(std::declval<const ControllerConfig&>(), std::declval<ControllerState&>(),
                                      std::declval<const contract::Status&>(),
                                      std::declval<const contract::Attitude&>(), std::declval<std::int64_t&>())));
  const ControllerConfig c = loadControllerConfig(std::string(GIMBALSIM_CONTROLLER_CONFIG_DIR) + "/default.yaml");
  ControllerState s;
  std::int64_t next_seq = 0;
  long long stale = 0, safe = 0, suspect = 0;
  const long long before = test::g_allocations.load();
  test::setEigenMallocAllowed(false);
  for (int k = 0; k < 4000; ++k) {
    contract::Attitude att;
    att.seq = k;
    att.gyro_rate[2] = 1e-3;
    noteAttitude(s, att);
    if (k >= 1000 && k < 1300 && k % 2 == 0) continue;  // no status this tick
    contract::Status st;
    st.seq = k >= 1000 && k < 1300 ? k - 60 : k;  // 60 ticks late for 0.3 s
    const double w = 0.1;                         // [rad/s] both axes turn
    st.rate[0] = st.rate[1] = w;
    st.angle[0] = k >= 2000 && k < 2500 ? w * 2.0 : w * st.seq * c.period;  // stuck over 2..2.5 s
    st.angle[1] = w * st.seq * c.period;
    const Answer a = answerStatus(c, s, st, att, next_seq);
    stale += a.flags.stale;
    safe += a.flags.safe;
    suspect += a.flags.encoder_suspect[0];
  }
  test::setEigenMallocAllowed(true);
  EXPECT_EQ(test::g_allocations.load() - before, 0);
  EXPECT_GT(stale, 100);
  EXPECT_EQ(safe, 0);
  EXPECT_GT(suspect, 400);
}

}  // namespace
}  // namespace gimbalsim::controllers
