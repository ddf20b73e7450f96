// The antenna's own sensors (firmware_sim/antenna_sensors.hpp, scene key
// sensors.antenna): the tracker's axes and sign on a hand-made geometry; in
// the closed loop on paper_spatial2_tracker its reading's size is the truth
// pointing error at every tick (play and tilt included) and the gyro the
// antenna's own rate; the schedule (rate, latency, stamps), noise, bias and
// outage, and the fault schedule's tracker faults; a scene without them has
// no message; bad keys refused by name.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "alloc_guard.hpp"
#include "closed_loop_util.hpp"
#include "gimbalsim/firmware_sim/antenna_sensors.hpp"
#include "gimbalsim/firmware_sim/bench_tick.hpp"
#include "gimbalsim/firmware_sim/fault_schedule_io.hpp"
#include "gimbalsim/firmware_sim/plant_scene.hpp"
#include "gimbalsim/pointing/tracker_axes.hpp"
#include "test_util.hpp"

namespace gimbalsim::controllers {
namespace {

constexpr double kT = 1e-3;  // control period [s]

firmware::PlantScene plant(const std::string& name, const std::vector<std::string>& sets = {}) {
  return firmware::loadPlantScene(test::scenePath(name), sets);
}

TEST(AntennaSensors, TrackerAxesAndSignOnThePapersGeometry) {
  // Boresight x, elevation axis y: u = y, v = x cross y = z.
  const pointing::TrackerAxes a = pointing::trackerAxes(Vec3::UnitY(), Vec3::UnitX());
  const Mat3 I = Mat3::Identity();
  // The target 0.01 rad up about +y from the boresight: the rotation onto it is +0.01 about u.
  const Vec3 up = Eigen::AngleAxisd(0.01, Vec3::UnitY()) * Vec3::UnitX();
  const Vec2 m1 = pointing::trackerReading(a, I, up);
  EXPECT_NEAR(m1(0), 0.01, 1e-15);
  EXPECT_NEAR(m1(1), 0.0, 1e-15);
  // About +z by -0.02, seen by an antenna turned 90 degrees about z: its own axes carry the reading.
  const Mat3 R = Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()).toRotationMatrix();
  const Vec3 left = Eigen::AngleAxisd(-0.02, Vec3::UnitZ()) * (R * Vec3::UnitX());
  const Vec2 m2 = pointing::trackerReading(a, R, left);
  EXPECT_NEAR(m2(0), 0.0, 1e-15);
  EXPECT_NEAR(m2(1), -0.02, 1e-15);
  // The rotation back in the frame F is what takes the boresight onto the target.
  const Vec3 eps = pointing::trackerRotation(a, R, m2);
  EXPECT_LT((Eigen::AngleAxisd(eps.norm(), eps.normalized()) * (R * Vec3::UnitX()) - left).norm(), 1e-15);
}

TEST(AntennaSensors, TrackerReadsThePointingErrorThePlayMakesAtEveryTick) {
  const firmware::PlantScene ps = plant("paper_spatial2_tracker", {"contact.clearance=1e-4"});
  ASSERT_TRUE(ps.sensors.antenna_sensors);
  // Encoders only: the play then moves the antenna by milliradians, a reading worth checking (the
  // default closes its loop on the tracker and keeps it within 2e-4 rad, MODEL.md 11.7).
  const ControllerConfig c = loadControllerConfig(test::defaultControllerConfig(), {"antenna.tracker=ignore"});
  ClosedLoopOptions opt;
  opt.duration = 4.0;
  double worst = 0.0, largest = 0.0;
  long long ticks = 0;
  const ClosedLoopResult r = runClosedLoop(ps, c, opt, [&](const TickRecord& t) {
    // Perfect, 1 kHz, no latency: each tick's own sample; |(u, v)| is the angle boresight-target.
    worst = std::max(worst, std::fabs(t.tracker.norm() - t.truth_error));
    largest = std::max(largest, t.truth_error);
    ++ticks;
  });
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(ticks, 4001);
  EXPECT_GT(largest, 1e-3);  // the tilting journal moves the antenna: a reading worth checking
  EXPECT_LT(worst, 1e-12 * std::max(1.0, largest));
}

/// Antenna messages of ticks 0 .. n-1 for an antenna at rest turned by R, rate w.
std::vector<contract::Antenna> run(const firmware::SensorParams& p, int n, const Vec3& target) {
  const Model m = test::model("paper_ideal");
  firmware::AntennaSensors s(m, p, kT);
  std::vector<contract::Antenna> out(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    s.sample(k, k * 1000, Mat3::Identity(), Vec3(0.1, -0.2, 0.3), target, out[static_cast<std::size_t>(k)]);
  }
  return out;
}

TEST(AntennaSensors, RateLatencyAndStampsFollowTheSchedule) {
  firmware::SensorParams p;
  p.antenna_sensors = true;
  p.tracker_rate = 100.0;       // a sample every 10 ticks
  p.tracker_latency = 0.025;    // delivered 25 ticks after it was taken
  const Vec3 target = Eigen::AngleAxisd(0.003, Vec3::UnitY()) * Vec3::UnitX();
  const auto a = run(p, 200, target);
  std::vector<int> valid;
  for (int k = 0; k < 200; ++k) {
    const contract::Antenna& m = a[static_cast<std::size_t>(k)];
    if (m.tracker_valid) {
      valid.push_back(k);
      EXPECT_NEAR(m.tracker_time, (k - 25) * kT, 1e-12) << k;
      EXPECT_NEAR(m.tracker_error[0], 0.003, 1e-15);
    }
    if (k < 25) EXPECT_EQ(m.tracker_time, -1.0) << k;  // none delivered yet
    EXPECT_EQ(m.gyro_rate[1], -0.2);                    // the gyro every tick, perfect
  }
  ASSERT_EQ(valid.size(), 18u);  // samples at ticks 0, 10, ..., 170 delivered by tick 199
  EXPECT_EQ(valid.front(), 25);
  EXPECT_EQ(valid[1], 35);
}

TEST(AntennaSensors, NoiseBiasAndOutageAreWhatTheKeysSay) {
  firmware::SensorParams p;
  p.antenna_sensors = true;
  p.tracker_noise = 1e-5;
  p.tracker_bias = Vec2(2e-5, -3e-5);
  p.antenna_gyro_noise = 1e-3;
  p.tracker_outage = Vec2(0.1, 0.2);
  const int n = 40000;
  const auto a = run(p, n, Vec3::UnitX());  // on target: the reading is bias and noise only
  double s[2] = {}, s2[2] = {}, g2 = 0.0;
  int used = 0;
  for (int k = 0; k < n; ++k) {
    const contract::Antenna& m = a[static_cast<std::size_t>(k)];
    const bool in_outage = k >= 100 && k <= 200;
    EXPECT_EQ(m.tracker_outage, in_outage ? 1 : 0) << k;
    if (in_outage) EXPECT_EQ(m.tracker_valid, 0) << k;
    const double e = m.gyro_rate[0] - 0.1;
    g2 += e * e;
    if (!m.tracker_valid) continue;
    ++used;
    for (int i = 0; i < 2; ++i) {
      const double d = m.tracker_error[i] - p.tracker_bias(i);
      s[i] += d, s2[i] += d * d;
    }
  }
  EXPECT_EQ(used, n - 101);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(s[i] / used, 0.0, 5e-5 / std::sqrt(used)) << i;  // the bias is the mean (5 sigma)
    EXPECT_NEAR(std::sqrt(s2[i] / used) / 1e-5, 1.0, 0.02) << i;
  }
  EXPECT_NEAR(std::sqrt(g2 / n) / 1e-3, 1.0, 0.02);
}

TEST(AntennaSensors, ASceneWithoutThemHasNoMessageAndTheRecordSaysNaN) {
  const firmware::PlantScene ps = plant("paper_ideal");
  EXPECT_FALSE(ps.sensors.antenna_sensors);
  const ControllerConfig c = loadControllerConfig(test::defaultControllerConfig());
  firmware::Config fc;
  fc.control_period = c.period;
  firmware::BenchTick<FloatingIdeal> tick(ps, fc, nullptr, &c.profile);
  EXPECT_EQ(tick.sample(0, 0, true).antenna, nullptr);
  ClosedLoopOptions opt;
  opt.duration = 0.01;
  bool all_nan = true;
  runClosedLoop(ps, c, opt, [&](const TickRecord& t) { all_nan = all_nan && std::isnan(t.tracker(0)); });
  EXPECT_TRUE(all_nan);
}

TEST(AntennaSensors, TheTickWithThemAllocatesNothing) {
  test::noteIfNotCheckedBuild();
  // Every antenna sensor setting on: noise, bias, a slower tracker with latency, an outage.
  const firmware::PlantScene ps = plant("paper_spatial2_tracker",
                                        {"sensors.tracker_noise=1e-5", "sensors.tracker_bias=[1e-5, -1e-5]",
                                         "sensors.tracker_rate=200", "sensors.tracker_latency=0.012",
                                         "sensors.tracker_outage=[0.1, 0.12]", "sensors.antenna_gyro_noise=1e-4",
                                         "sensors.antenna_gyro_bias=[1e-4, 0, -1e-4]"});
  const ControllerConfig c = loadControllerConfig(test::defaultControllerConfig());
  firmware::Config fc;
  fc.control_period = c.period;
  firmware::BenchTick<Variant<true, ClearanceKind::Ideal, ClearanceKind::Spatial, true>> tick(ps, fc, nullptr,
                                                                                              &c.profile);
  for (int k = 0; k < 10; ++k) {
    tick.sample(k, k * 1000, true);
    tick.advance();
  }
  int delivered = 0;
  const long long before = test::g_allocations.load();
  test::setEigenMallocAllowed(false);
  for (int k = 10; k < 300; ++k) {
    delivered += tick.sample(k, k * 1000, k % 3 == 0).antenna->tracker_valid;
    tick.advance();
  }
  test::setEigenMallocAllowed(true);
  EXPECT_EQ(test::g_allocations.load() - before, 0) << "heap allocations in 290 ticks";
  // Samples at ticks 0, 5, ..., 285 fall due in ticks 12 .. 297: 58, less the 5 not taken in the outage
  // [100, 120] and the 2 (ticks 90, 95) that fall due inside it: 51.
  EXPECT_EQ(delivered, 51);
}

TEST(AntennaSensors, TheTrackersScheduledFaultsActOnItsMessage) {
  const firmware::PlantScene ps = plant("paper_spatial2_tracker");
  const ControllerConfig c = loadControllerConfig(test::defaultControllerConfig());
  firmware::Config fc;
  fc.control_period = c.period;
  const firmware::FaultSchedule f = firmware::loadFaultScheduleText(
      "faults:\n  - {type: tracker_outage, start: 0.01, end: 0.02}\n"
      "  - {type: tracker_dropout, start: 0.03, end: 0.04}\n"
      "  - {type: tracker_bias, start: 0.05, end: 0.06, bias: [2.0e-4, -1.0e-4]}\n", "f.yaml");
  using V = Variant<true, ClearanceKind::Ideal, ClearanceKind::Spatial, true>;
  firmware::BenchTick<V> faulty(ps, fc, &f, &c.profile), clean(ps, fc, nullptr, &c.profile);
  for (int k = 0; k < 70; ++k) {  // no commands: both plants move alike, so the readings differ by the faults only
    const contract::Antenna a = *faulty.sample(k, k * 1000, false).antenna, b = *clean.sample(k, k * 1000, false).antenna;
    const bool outage = k >= 10 && k < 20, dropout = k >= 30 && k < 40, biased = k >= 50 && k < 60;
    EXPECT_EQ(a.tracker_outage, outage ? 1 : 0) << k;
    EXPECT_EQ(a.tracker_valid, outage || dropout ? 0 : 1) << k;  // a dropout loses the reading, not the lock
    if (outage || dropout) {
      EXPECT_DOUBLE_EQ(a.tracker_time, outage ? 0.009 : 0.029) << k;  // the last reading (the tick before) held
    } else {
      EXPECT_DOUBLE_EQ(a.tracker_error[0], b.tracker_error[0] + (biased ? 2.0e-4 : 0.0)) << k;
      EXPECT_DOUBLE_EQ(a.tracker_error[1], b.tracker_error[1] - (biased ? 1.0e-4 : 0.0)) << k;
    }
    faulty.advance();
    clean.advance();
  }
}

TEST(AntennaSensors, TheRecordHasNoReadingBeforeTheFirstDelivery) {
  // 8 ms of latency: ticks 0..7 have no reading yet (they read 0, as if on target).
  const firmware::PlantScene ps = plant("paper_spatial2_tracker", {"sensors.tracker_latency=0.0075"});
  const ControllerConfig c = loadControllerConfig(test::defaultControllerConfig());
  ClosedLoopOptions opt;
  opt.duration = 0.02;
  std::vector<double> u;
  const ClosedLoopResult r = runClosedLoop(ps, c, opt, [&](const TickRecord& t) { u.push_back(t.tracker(0)); });
  ASSERT_TRUE(r.ok) << r.error;  // no reading is no numerical trouble
  ASSERT_EQ(u.size(), 21u);
  for (int k = 0; k < 21; ++k) EXPECT_EQ(std::isnan(u[static_cast<std::size_t>(k)]), k < 8) << k;
}

TEST(AntennaSensors, BadKeysAreRefusedByName) {
  const auto refused = [](const std::vector<std::string>& sets, const std::string& key) {
    try {
      plant("paper_spatial2_tracker", sets);
    } catch (const InputError& e) {
      return std::string(e.what()).find(key) != std::string::npos;
    }
    return false;
  };
  EXPECT_TRUE(refused({"sensors.tracker_latency=0.01"}, "sensors.tracker_latency"));  // 10 periods at 1 kHz
  EXPECT_TRUE(refused({"sensors.tracker_outage=[2, 1]"}, "sensors.tracker_outage"));
  EXPECT_TRUE(refused({"sensors.tracker_rate=0"}, "sensors.tracker_rate"));
  EXPECT_TRUE(refused({"sensors.antenna=monopulse"}, "sensors.antenna"));
}

}  // namespace
}  // namespace gimbalsim::controllers
