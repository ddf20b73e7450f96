// The attitude sensors of the plant (firmware/attitude_sensors.hpp): rate
// gyro noise and bias random walk statistics, star tracker sample instants,
// latency, timestamps and outage, perfect sensors = truth bit for bit (also
// through the firmware core), determinism per seed, and the refusal of bad
// sensors.* scene keys naming the key. Zero allocation per tick with the
// sensors on is in firmware_core_test.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "gimbalsim/firmware_sim/attitude_sensors.hpp"
#include "gimbalsim/firmware_sim/firmware.hpp"
#include "test_util.hpp"

namespace gimbalsim::firmware {
namespace {

constexpr double kT = 1e-3;  // control period [s]

/// A base turning about a fixed axis at 0.5 rad/s: the true attitude at t.
Quat trueAttitude(double t) { return Quat(Eigen::AngleAxisd(0.5 * t, Vec3(1.0, 2.0, 2.0) / 3.0)); }
const Vec3 kTrueRate(0.1, -0.2, 0.3);

/// Attitude messages of ticks 0 .. n-1.
std::vector<Attitude> run(const SensorParams& p, int n, double T = kT) {
  AttitudeSensors s(p, T);
  std::vector<Attitude> out(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) s.sample(k, k * 1000, trueAttitude(k * T), kTrueRate, out[static_cast<std::size_t>(k)]);
  return out;
}

std::vector<int> validTicks(const std::vector<Attitude>& a) {
  std::vector<int> v;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (a[k].star_valid) v.push_back(static_cast<int>(k));
  }
  return v;
}

bool sameQuat(const double* q, const Quat& r) {
  return q[0] == r.w() && q[1] == r.x() && q[2] == r.y() && q[3] == r.z();
}

TEST(FirmwareAttitudeSensors, GyroWhiteNoiseHasItsSigmaAndNoMean) {
  SensorParams p;
  p.gyro_noise = 0.01;
  const auto a = run(p, 200000);
  double sum = 0.0, sum2 = 0.0;
  for (const Attitude& m : a) {
    for (int i = 0; i < 3; ++i) {
      const double e = m.gyro_rate[i] - kTrueRate(i);
      sum += e, sum2 += e * e;
    }
  }
  const double n = 3.0 * static_cast<double>(a.size());
  EXPECT_NEAR(sum / n, 0.0, 5.0 * 0.01 / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(sum2 / n) / 0.01, 1.0, 0.01);
  EXPECT_EQ(a[1234].gyro_time, 1234 * kT);
}

TEST(FirmwareAttitudeSensors, GyroBiasRandomWalkGrowsLikeSigmaSqrtTime) {
  // Many independent gyros (seeds): the bias spread at tick k is walk * sqrt(k T) about gyro_bias.
  SensorParams p;
  p.gyro_bias = Vec3(1e-3, 0.0, -2e-3);
  p.gyro_bias_walk = 0.002;
  constexpr int kRuns = 4000, kTicks = 251;
  double mean[2] = {}, var[2] = {};
  const int at[2] = {125, 250};
  for (int r = 0; r < kRuns; ++r) {
    p.seed = 1000 + r;
    AttitudeSensors s(p, kT);
    Attitude m;
    for (int k = 0; k < kTicks; ++k) {
      s.sample(k, 0, Quat::Identity(), Vec3::Zero(), m);
      for (int j = 0; j < 2; ++j) {
        if (k != at[j]) continue;
        for (int i = 0; i < 3; ++i) {
          const double e = m.gyro_rate[i] - p.gyro_bias(i);
          mean[j] += e, var[j] += e * e;
        }
      }
    }
  }
  for (int j = 0; j < 2; ++j) {
    const double n = 3.0 * kRuns, expected = p.gyro_bias_walk * p.gyro_bias_walk * at[j] * kT;
    EXPECT_NEAR(mean[j] / n, 0.0, 5.0 * std::sqrt(expected / n)) << "tick " << at[j];
    EXPECT_NEAR(var[j] / n / expected, 1.0, 0.05) << "tick " << at[j];
  }
  // Tick 0 carries exactly the constant bias.
  p.seed = 1;
  const auto a = run(p, 1);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(a[0].gyro_rate[i], kTrueRate(i) + p.gyro_bias(i));
}

TEST(FirmwareAttitudeSensors, StarTrackerNoiseIsASmallRotationWithItsSigmaPerAxis) {
  SensorParams p;
  p.star_tracker_rate = 1000.0;  // a sample every tick
  p.star_tracker_noise = 1e-4;
  const auto a = run(p, 30000);
  double sum2[3] = {};
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_TRUE(a[k].star_valid);
    const double* q = a[k].star_quaternion;
    const Quat meas(q[0], q[1], q[2], q[3]);
    EXPECT_NEAR(meas.norm(), 1.0, 1e-14);
    const Quat dq = trueAttitude(a[k].star_time).conjugate() * meas;  // q_true^-1 q_meas: base frame
    for (int i = 0; i < 3; ++i) sum2[i] += 4.0 * dq.vec()(i) * dq.vec()(i) / (dq.w() * dq.w());
  }
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(std::sqrt(sum2[i] / a.size()) / 1e-4, 1.0, 0.02) << "axis " << i;
}

TEST(FirmwareAttitudeSensors, StarTrackerSamplesAtItsRateDeliveredAfterItsLatencyWithItsOwnTime) {
  SensorParams p;  // 10 Hz
  p.star_tracker_latency = 0.035;
  const auto a = run(p, 1000);
  const std::vector<int> expected{35, 135, 235, 335, 435, 535, 635, 735, 835, 935};
  EXPECT_EQ(validTicks(a), expected);
  for (int k : expected) {
    const int ks = k - 35;
    EXPECT_EQ(a[k].star_time, ks * kT) << "tick " << k;
    EXPECT_TRUE(sameQuat(a[k].star_quaternion, trueAttitude(ks * kT))) << "tick " << k;
    EXPECT_EQ(a[k].star_outage, 0);
  }
  // Between deliveries the last sample is held, flagged not new; none before the first.
  EXPECT_EQ(a[34].star_time, -1.0);
  EXPECT_EQ(a[100].star_time, 0.0);
  EXPECT_TRUE(sameQuat(a[100].star_quaternion, trueAttitude(0.0)));

  // A period that is not a multiple of the control period: the first tick at or after j / 3 s.
  p.star_tracker_rate = 3.0;
  p.star_tracker_latency = 0.0;
  EXPECT_EQ(validTicks(run(p, 1001)), (std::vector<int>{0, 334, 667, 1000}));
  // Faster than the control rate: one sample per tick.
  p.star_tracker_rate = 2500.0;
  EXPECT_EQ(validTicks(run(p, 5)), (std::vector<int>{0, 1, 2, 3, 4}));
  // The longest latency allowed (just under 8 periods) keeps every sample.
  p.star_tracker_rate = 10.0;
  p.star_tracker_latency = 0.799;
  const auto late = validTicks(run(p, 2000));
  ASSERT_EQ(late.size(), 13u);
  for (std::size_t j = 0; j < late.size(); ++j) EXPECT_EQ(late[j], 799 + 100 * static_cast<int>(j));
}

TEST(FirmwareAttitudeSensors, OutageIsFlaggedAndDeliversNoSample) {
  SensorParams p;  // 10 Hz
  p.star_tracker_latency = 0.035;
  p.star_tracker_outage = Vec2(0.25, 0.52);
  const auto a = run(p, 1000);
  EXPECT_EQ(validTicks(a), (std::vector<int>{35, 135, 235, 635, 735, 835, 935}));
  for (int k = 0; k < 1000; ++k) EXPECT_EQ(a[k].star_outage, (k >= 250 && k <= 520) ? 1 : 0) << "tick " << k;
  // A sample taken before the outage and due during it is dropped.
  p.star_tracker_latency = 0.06;
  EXPECT_EQ(validTicks(run(p, 1000)), (std::vector<int>{60, 160, 660, 760, 860, 960}));
}

TEST(FirmwareAttitudeSensors, SameSeedSameNumbersOtherSeedOtherNumbers) {
  SensorParams p;
  p.star_tracker_noise = 1e-4;
  p.star_tracker_latency = 0.02;
  p.gyro_bias_walk = 1e-3;
  p.gyro_noise = 1e-3;
  p.seed = 7;
  const auto a = run(p, 2000), b = run(p, 2000);
  ASSERT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(Attitude)), 0);
  p.seed = 8;
  const auto c = run(p, 2000);
  int gyro_differs = 0, star_differs = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    gyro_differs += a[k].gyro_rate[0] != c[k].gyro_rate[0];
    star_differs += a[k].star_valid && a[k].star_quaternion[1] != c[k].star_quaternion[1];
  }
  EXPECT_EQ(gyro_differs, 2000);
  EXPECT_EQ(star_differs, 20);
  // The streams are separate: star tracker noise does not move the gyro numbers.
  p.star_tracker_noise = 0.0;
  const auto d = run(p, 2000);
  for (std::size_t k = 0; k < a.size(); ++k) ASSERT_EQ(d[k].gyro_rate[2], c[k].gyro_rate[2]);
  EXPECT_NE(streamSeed(7, kGyroStream), streamSeed(7, kStarTrackerStream));
  EXPECT_NE(streamSeed(7, kGyroStream), 7u);
}

Command torqueCommand(std::int64_t seq, std::int64_t status_seq) {
  Command c;
  c.seq = seq;
  c.status_seq = status_seq;
  c.mode = kModeTorque;
  c.torque[0] = 5.0, c.torque[1] = 10.0;
  return c;
}

TEST(FirmwareAttitudeSensors, PerfectSensorsByDefaultGiveTheTruthExactly) {
  const PlantScene sc = test::plant("paper_clearance");
  const SensorParams d{};
  EXPECT_EQ(d.star_tracker_noise, 0.0);
  EXPECT_EQ(d.star_tracker_latency, 0.0);
  EXPECT_EQ(d.gyro_bias, Vec3::Zero());
  EXPECT_EQ(d.gyro_bias_walk, 0.0);
  EXPECT_EQ(d.gyro_noise, 0.0);
  EXPECT_EQ(d.star_tracker_outage, Vec2::Zero());
  Firmware<FloatingClearanceFriction> fw(sc, Config{});
  for (int k = 0; k < 350; ++k) {
    fw.receive(torqueCommand(k + 1, k - 1));
    fw.sample(k * 1000, true);
    const Attitude& a = fw.attitude();
    const Truth& t = fw.truth();
    ASSERT_EQ(a.seq, k);
    ASSERT_EQ(a.utime, k * 1000);
    ASSERT_EQ(std::memcmp(a.gyro_rate, t.base_rate, sizeof a.gyro_rate), 0) << "tick " << k;
    ASSERT_EQ(a.star_valid, k % 100 == 0 ? 1 : 0) << "tick " << k;
    if (a.star_valid) {
      ASSERT_EQ(std::memcmp(a.star_quaternion, t.base_quaternion, sizeof a.star_quaternion), 0) << "tick " << k;
      ASSERT_EQ(a.star_time, k * 1e-3);
    }
    fw.advance();
  }
  EXPECT_GT(std::fabs(fw.truth().base_rate[2]), 1e-6) << "the base must turn";
}

TEST(FirmwareAttitudeSensors, FixedBaseReadsIdentityAndZeroRate) {
  const PlantScene sc = test::plant("paper_ideal", {"structure.base=fixed", "sensors.gyro_bias=[0.1, 0.2, 0.3]"});
  Firmware<FixedIdeal> fw(sc, Config{});
  fw.tick(0);
  EXPECT_EQ(fw.attitude().gyro_rate[1], 0.2);
  EXPECT_TRUE(sameQuat(fw.attitude().star_quaternion, Quat::Identity()));
}

std::string refusal(const std::string& set) {
  try {
    test::plant("paper_ideal", {set});
  } catch (const SceneError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(FirmwareAttitudeKeys, BadValuesAreRefusedNamingTheKey) {
  const std::pair<const char*, const char*> cases[] = {
      {"sensors.star_tracker_rate=0", "key 'sensors.star_tracker_rate': must be in [1e-06, 1e+06], got 0"},
      // Ranges the loop honours: a rate at which the sample index overflowed and the loop hung; NaN-making values.
      {"sensors.star_tracker_rate=1e20", "key 'sensors.star_tracker_rate': must be in [1e-06, 1e+06], got 1e+20"},
      {"sensors.encoder_resolution=1e-300", "key 'sensors.encoder_resolution': must be 0 or in [1e-12, 1], got 1e-300"},
      {"sensors.encoder_resolution=1e-310", "key 'sensors.encoder_resolution': '1e-310' underflows a double"},
      {"sensors.gyro_bias=[1e300, 0, 0]", "key 'sensors.gyro_bias': must be in [-1, 1]"},
      {"sensors.star_tracker_noise=-0.5", "key 'sensors.star_tracker_noise': must be in [0, 1], got -0.5"},
      {"sensors.star_tracker_latency=-0.01", "key 'sensors.star_tracker_latency': must be in [0, 1e+06], got -0.01"},
      {"sensors.star_tracker_latency=0.8",
       "key 'sensors.star_tracker_latency': must be < 8 star tracker periods (0.8 s at 10 Hz)"},
      {"sensors.star_tracker_outage=[2, 1]",
       "key 'sensors.star_tracker_outage': end must be > start ([0, 0] for none), got [2, 1]"},
      // (pass 98) a window of no length was none, recorded as an outage, never flagged
      {"sensors.star_tracker_outage=[0.2, 0.2]",
       "key 'sensors.star_tracker_outage': end must be > start ([0, 0] for none), got [0.2, 0.2]"},
      {"sensors.tracker_outage=[0.2, 0.2]",
       "key 'sensors.tracker_outage': end must be > start ([0, 0] for none), got [0.2, 0.2]"},
      {"sensors.star_tracker_outage=[-1, 1]", "key 'sensors.star_tracker_outage': must be in [0, 1e+09]"},
      {"sensors.gyro_bias=[1, 2]", "key 'sensors.gyro_bias'"},
      {"sensors.gyro_bias_walk=-1", "key 'sensors.gyro_bias_walk': must be in [0, 1], got -1"},
      {"sensors.gyro_noise=-1", "key 'sensors.gyro_noise': must be in [0, 100], got -1"},
  };
  for (const auto& [set, says] : cases) {
    const std::string why = refusal(set);
    EXPECT_NE(why.find(says), std::string::npos) << set << " -> " << why;
    EXPECT_NE(why.find(std::string("--set #1 '") + set + "'"), std::string::npos) << why;
  }
  const PlantScene ok = test::plant("paper_ideal", {"sensors.star_tracker_rate=50", "sensors.star_tracker_latency=0.15",
                                               "sensors.star_tracker_outage=[1, 2.5]", "sensors.gyro_bias=[1e-3, 0, 0]"});
  EXPECT_EQ(ok.sensors.star_tracker_outage, Vec2(1.0, 2.5));
}

}  // namespace
}  // namespace gimbalsim::firmware
