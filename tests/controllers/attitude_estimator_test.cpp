// Attitude estimator (attitude_estimator.hpp) on a simulated rotating base:
// 1 kHz gyro (bias, white noise), 10 Hz star tracker (noise, latency,
// outage). Perfect sensors: the estimate is the truth to round-off; a gyro
// bias is estimated and the attitude error goes to ~0; an outage grows the
// error only by the integrated gyro error; a late sample is used without an
// error jump; the steady error scales with the star tracker's noise; the
// update allocates nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <random>
#include <utility>
#include <vector>

#include "alloc_guard.hpp"
#include "gimbalsim/controllers/attitude_estimator.hpp"

namespace gimbalsim::controllers {
namespace {

struct Scenario {
  double dt = 1e-3;                   ///< control period [s]
  int star_every = 100;               ///< star tracker period in control periods (10 Hz)
  double latency = 0.0;               ///< star tracker latency [s]
  double star_noise = 0.0;            ///< sigma per axis [rad]
  Vec3 gyro_bias = Vec3::Zero();      ///< [rad/s], base frame
  double gyro_noise = 0.0;            ///< white, per sample [rad/s]
  double outage_start = -1.0, outage_end = -1.0;  ///< no samples taken in [start, end) [s]
  Vec3 bias_kick = Vec3::Zero();      ///< added to the bias estimate at outage_start [rad/s]
  bool constant_rate = false;
  double duration = 20.0;             ///< [s]
  AttitudeEstimatorParams params;
  std::uint64_t seed = 7;

  /// True base rate, base frame [rad/s].
  Vec3 rate(double t) const {
    if (constant_rate) return {0.01, -0.02, 0.015};
    return {0.02 * std::sin(0.5 * t), 0.01 * std::cos(0.3 * t), 0.015};
  }
};

struct Trace {
  std::vector<double> t;
  std::vector<Vec3> err_W;          ///< Log(q_true q_hat^-1), inertial frame [rad]
  std::vector<double> bias_err;     ///< |bias_hat - bias| [rad/s]
  std::vector<double> gyro_err_int; ///< running integral of |gyro - bias_hat - rate| [rad]
  AttitudeEstimatorState last;
  long long rejected = 0, used = 0;
  double err(std::size_t k) const { return err_W[k].norm(); }
  /// Largest error in [t0, t1).
  double maxErr(double t0, double t1) const {
    double m = 0.0;
    for (std::size_t k = 0; k < t.size(); ++k) {
      if (t[k] >= t0 && t[k] < t1) m = std::max(m, err(k));
    }
    return m;
  }
};

/// Truth propagated with rotation matrices (rate held over each period), the
/// estimator with its quaternions: independent code paths.
Trace run(const Scenario& sc) {
  std::mt19937_64 rng(sc.seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  auto noise3 = [&](double s) { return Vec3(s * n01(rng), s * n01(rng), s * n01(rng)); };
  const long long N = std::llround(sc.duration / sc.dt);
  Trace tr;
  tr.t.reserve(N), tr.err_W.reserve(N), tr.bias_err.reserve(N), tr.gyro_err_int.reserve(N);
  Mat3 R = Quat(0.8, -0.2, 0.4, 0.1).normalized().toRotationMatrix();  // true R_WB
  AttitudeEstimatorState s;
  std::deque<std::pair<double, Quat>> in_flight;  // (t_s, sample)
  double gyro_err_int = 0.0;
  for (long long k = 0; k < N; ++k) {
    const double t = static_cast<double>(k) * sc.dt;
    const bool outage = t >= sc.outage_start && t < sc.outage_end;
    if (k % sc.star_every == 0 && !outage) {
      in_flight.emplace_back(t, Quat(R) * expRotation(noise3(sc.star_noise)));
    }
    if (std::abs(t - sc.outage_start) < 0.5 * sc.dt) s.bias_B += sc.bias_kick;
    while (!in_flight.empty() && in_flight.front().first + sc.latency <= t + 1e-9) {
      correct(sc.params, s, in_flight.front().first, in_flight.front().second);
      in_flight.pop_front();
    }
    tr.t.push_back(t);
    tr.err_W.push_back(logRotation(Quat(R) * s.q_WB.conjugate()));
    tr.bias_err.push_back((s.bias_B - sc.gyro_bias).norm());
    tr.gyro_err_int.push_back(gyro_err_int);
    const Vec3 w = sc.rate(t), gyro = w + sc.gyro_bias + noise3(sc.gyro_noise);
    gyro_err_int += (gyro - s.bias_B - w).norm() * sc.dt;
    propagate(sc.params, s, t + sc.dt, gyro);
    R = R * axisAngle(w.normalized(), w.norm() * sc.dt);
  }
  tr.last = s;
  tr.rejected = s.samples_rejected, tr.used = s.samples_used;
  return tr;
}

TEST(AttitudeEstimator, PerfectSensorsGiveTheTruthToRoundOff) {
  for (const bool constant : {false, true}) {
    Scenario sc;
    sc.constant_rate = constant;
    sc.duration = 30.0;
    const Trace tr = run(sc);
    EXPECT_LT(tr.maxErr(0.0, sc.duration), 1e-12);
    EXPECT_LT(tr.bias_err.back(), 1e-13);
    EXPECT_EQ(tr.rejected, 0);
    EXPECT_EQ(tr.used, 300);
  }
}

TEST(AttitudeEstimator, GyroBiasIsEstimatedAndTheErrorVanishes) {
  Scenario sc;
  sc.gyro_bias = {2e-4, -1e-4, 1.5e-4};  // about 40 deg/h
  sc.duration = 150.0;
  const Trace tr = run(sc);
  std::printf("bias error: %.3g at 0 s, %.3g at 50 s, %.3g at 150 s; attitude error %.3g at 20 s, %.3g at 150 s\n",
              tr.bias_err.front(), tr.bias_err[50000], tr.bias_err.back(), tr.err(20000), tr.err(tr.t.size() - 1));
  EXPECT_GT(tr.maxErr(1.0, 10.0), 1e-5);  // the bias shows before it is learnt
  EXPECT_LT(tr.bias_err.back(), 1e-9);
  EXPECT_LT(tr.maxErr(140.0, 150.0), 1e-9);
}

TEST(AttitudeEstimator, OutageCoastsOnTheGyro) {
  Scenario sc;
  sc.gyro_bias = {2e-4, -1e-4, 1.5e-4};
  sc.gyro_noise = 1e-5;
  sc.outage_start = 100.0, sc.outage_end = 120.0;
  sc.bias_kick = {1e-5, 0.0, 0.0};  // a bias estimate error to coast on
  sc.duration = 200.0;
  const Trace tr = run(sc);
  const std::size_t k0 = 100000, k1 = 119999;  // the last tick before a sample comes again
  const double e0 = tr.err(k0), grown = tr.err(k1) - e0;
  const double integrated = tr.gyro_err_int[k1] - tr.gyro_err_int[k0];
  std::printf("outage: error %.3g -> %.3g rad over 20 s; integrated |gyro error| %.3g rad\n", e0, tr.err(k1),
              integrated);
  EXPECT_LT(e0, 1e-6);
  for (std::size_t k = k0; k <= k1; ++k) {  // never more than the gyro error integrated since the outage began
    ASSERT_LE(tr.err(k), e0 + (tr.gyro_err_int[k] - tr.gyro_err_int[k0]) + 1e-12) << "t = " << tr.t[k];
  }
  EXPECT_GT(grown, 0.9 * 1e-5 * 20.0);  // the bias error's share, nearly fixed in W over 20 s
  EXPECT_LT(grown, 1.1 * 1e-5 * 20.0);
  EXPECT_LT(tr.maxErr(190.0, 200.0), 1e-5);  // recovered
  EXPECT_LT(tr.bias_err.back(), 1e-6);
}

TEST(AttitudeEstimator, LateSamplesAreComparedWithThePastEstimate) {
  for (const bool constant : {true, false}) {
    Scenario sc;
    sc.constant_rate = constant;
    sc.latency = 0.1;
    sc.duration = 30.0;
    const Trace tr = run(sc);
    // Constant rate: slerp in the ring is exact; varying rate: its error
    // (rate change over the 5 ms spacing) is all that is left.
    EXPECT_LT(tr.maxErr(0.1, sc.duration), constant ? 1e-12 : 1e-7);
    EXPECT_EQ(tr.rejected, 0);
    EXPECT_EQ(tr.used, 299);
  }
  Scenario sc;
  sc.latency = 0.1;
  sc.gyro_bias = {2e-4, -1e-4, 1.5e-4};
  sc.duration = 150.0;
  const Trace tr = run(sc);
  EXPECT_LT(tr.bias_err.back(), 1e-8);
  EXPECT_LT(tr.maxErr(140.0, 150.0), 1e-7);
}

TEST(AttitudeEstimator, SamplesOutsideTheRingOrOrderAreRefused) {
  Scenario sc;
  sc.latency = 0.5;  // > 64 x 5 ms of ring
  sc.duration = 2.0;
  const Trace tr = run(sc);
  EXPECT_EQ(tr.used, 0);
  EXPECT_EQ(tr.rejected, 15);
  EXPECT_FALSE(tr.last.initialized);

  const AttitudeEstimatorParams p;
  AttitudeEstimatorState s;
  for (int k = 1; k <= 100; ++k) propagate(p, s, 1e-3 * k, Vec3(0.0, 0.0, 0.01));
  const Quat q = s.q_WB;
  EXPECT_EQ(correct(p, s, 0.2, q), SampleStatus::Future);
  EXPECT_EQ(correct(p, s, 0.05, q), SampleStatus::Initialized);
  EXPECT_EQ(correct(p, s, 0.05, q), SampleStatus::OutOfOrder);
  EXPECT_EQ(correct(p, s, 0.04, q), SampleStatus::OutOfOrder);
  EXPECT_EQ(correct(p, s, 0.1, q), SampleStatus::Corrected);
  EXPECT_STREQ(describe(SampleStatus::TooOld), "too old (before the ring)");
}

// historySpan is the latency from which the ring holds no sample's time:
// every sample is dropped at it, and some are used two ring spacings below
// (a sweep refuses the star tracker's keys beyond it: _idle_sensors.py).
TEST(AttitudeEstimator, HistorySpanIsTheLatencyFromWhichEverySampleIsTooOld) {
  const AttitudeEstimatorParams p;
  EXPECT_DOUBLE_EQ(historySpan(p, 1e-3), 0.32);   // 64 entries 5 ms apart
  EXPECT_DOUBLE_EQ(historySpan(p, 3e-3), 0.384);  // 5 ms rounded up to two periods
  EXPECT_DOUBLE_EQ(historySpan(p, 7e-3), 0.448);  // one period
  for (const double dt : {1e-3, 2e-3, 3e-3, 7e-3}) {
    Scenario sc;
    sc.dt = dt;
    sc.star_every = 3;
    sc.duration = 2.0;
    sc.latency = historySpan(p, dt);
    const Trace at = run(sc);
    long long delivered = 0;  // every sample whose latency has passed by the last tick (run()'s rule)
    const long long N = std::llround(sc.duration / dt);
    for (long long k = 0; k < N; k += sc.star_every) delivered += k * dt + sc.latency <= (N - 1) * dt + 1e-9;
    EXPECT_EQ(at.used, 0) << dt;
    EXPECT_EQ(at.rejected, delivered) << dt;
    EXPECT_GT(delivered, 50) << dt;
    sc.latency -= 2.0 * historySpan(p, dt) / p.history_length;
    EXPECT_GT(run(sc).used, 0) << dt;
  }
}

double steadyStd(double star_noise) {
  Scenario sc;
  sc.gyro_bias = {2e-4, -1e-4, 1.5e-4};
  sc.star_noise = star_noise;
  sc.latency = 0.05;
  sc.duration = 300.0;
  const Trace tr = run(sc);
  double sum = 0.0, sum2 = 0.0;
  long long n = 0;
  for (std::size_t k = 100000; k < tr.err_W.size(); ++k) {
    for (int i = 0; i < 3; ++i) sum += tr.err_W[k](i), sum2 += tr.err_W[k](i) * tr.err_W[k](i), ++n;
  }
  const double mean = sum / n;
  return std::sqrt(sum2 / n - mean * mean);
}

TEST(AttitudeEstimator, SteadyErrorScalesWithTheStarTrackerNoise) {
  const double lo = steadyStd(1e-5), hi = steadyStd(1e-4);
  std::printf("steady error std per axis: %.3g rad (noise 1e-5), %.3g rad (noise 1e-4), ratio %.2f\n", lo, hi,
              hi / lo);
  EXPECT_GE(hi / lo, 7.0);
  EXPECT_LE(hi / lo, 13.0);
  EXPECT_LT(hi, 0.5e-4);  // filtered: well below the sample noise
}

TEST(AttitudeEstimator, UpdateAllocatesNothing) {
  EXPECT_GE(test::probeAllocations(), 1);
  test::noteIfNotCheckedBuild();
  const AttitudeEstimatorParams p;
  AttitudeEstimatorState s;
  const long long before = test::g_allocations.load();
  test::setEigenMallocAllowed(false);
  Quat q = Quat::Identity();
  for (int k = 0; k < 20000; ++k) {  // wraps the ring many times
    const double t = 1e-3 * k;
    if (k % 100 == 0) correct(p, s, t - 0.05 * (k > 0), q);
    propagate(p, s, t + 1e-3, Vec3(1e-3, -2e-3, 0.01));
    q = q * expRotation(Vec3(0.0, 0.0, 1e-5));
  }
  test::setEigenMallocAllowed(true);
  EXPECT_EQ(test::g_allocations.load() - before, 0);
  EXPECT_TRUE(s.initialized);
  EXPECT_EQ(s.samples_used, 200);
}

using P = const AttitudeEstimatorParams&;
using S = AttitudeEstimatorState&;
static_assert(noexcept(propagate(std::declval<P>(), std::declval<S>(), 0.0, std::declval<const Vec3&>())));
static_assert(noexcept(correct(std::declval<P>(), std::declval<S>(), 0.0, std::declval<const Quat&>())));

}  // namespace
}  // namespace gimbalsim::controllers
