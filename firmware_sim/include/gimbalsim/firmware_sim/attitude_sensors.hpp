// The base attitude sensors of the plant: a star tracker and a rate gyro,
// seeded and deterministic (the project's own generator, sensor_noise.hpp:
// the same seed gives the same numbers on every standard library). The
// firmware core (firmware.hpp) calls sample() once per control tick, so
// firmware_sim and the in-process closed loop measure alike. sample() is
// noexcept and allocation-free. Parameters: SensorParams (run_spec.hpp), the
// scene keys sensors.star_tracker_* and sensors.gyro_* (defaults: perfect).
//
// Tick k at t_k = k T (T the control period):
//  - rate gyro, every tick, base frame: w_meas = w_true + b_k + gyro_noise n,
//    then b_{k+1} = b_k + gyro_bias_walk sqrt(T) n' (b_0 = gyro_bias);
//  - star tracker: on its schedule (sample_schedule.hpp): sample j belongs
//    to the instant j P (P = 1 / rate) and is taken in the first tick at or
//    after it (t_s = t_k); at most one sample per tick. Its quaternion
//    (base -> inertial, w x y z) is q_true * dq, dq the rotation by a vector
//    of N(0, star_tracker_noise^2) components in the base frame. It is
//    delivered in the first tick at or after t_s + latency, stamped t_s; when
//    several fall due in one tick the newest is delivered. Outage [start, end]
//    (active when end > start): in ticks with t_k inside it no sample is taken
//    or delivered (those due are dropped) and star_outage is set.
//    Between deliveries the message holds the last delivered sample with
//    star_valid = 0 (star_time = -1 before the first one).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "gimbalsim/dynamics/run_spec.hpp"
#include "gimbalsim/firmware_sim/sensor_params.hpp"
#include "gimbalsim/contract/messages.hpp"
#include "gimbalsim/firmware_sim/sample_schedule.hpp"
#include "gimbalsim/firmware_sim/sensor_noise.hpp"

namespace gimbalsim::firmware {
// The bench messages are the contract's (lcmtypes/contract), shared with the controller.
using namespace gimbalsim::contract;  // NOLINT(google-build-using-namespace)

/// Sensor streams derived from sensors.seed (streamSeed); the encoders use the seed itself.
enum SensorStream : std::uint64_t { kGyroStream = 1, kStarTrackerStream = 2, kTrackerStream = 3, kAntennaGyroStream = 4 };

class AttitudeSensors {
 public:
  /// p must pass the scene checks (rate > 0, latency below its limit) and
  /// control_period be > 0; other values only keep the arithmetic defined.
  AttitudeSensors(const SensorParams& p, double control_period) noexcept
      : p_(p),
        T_(control_period > 0.0 ? control_period : 1.0),
        gyro_noise_(streamSeed(static_cast<std::uint64_t>(p.seed), kGyroStream)),
        star_noise_(streamSeed(static_cast<std::uint64_t>(p.seed), kStarTrackerStream)),
        bias_(p.gyro_bias),
        star_(p.star_tracker_rate, p.star_tracker_latency, T_, Star::Sample{0, -1.0, {1.0, 0.0, 0.0, 0.0}}),
        outage_(p.star_tracker_outage(1) > p.star_tracker_outage(0)) {}

  /// Measures tick k (t_k = k T) from the true attitude q_true (base ->
  /// inertial) and rate w_true (base frame [rad/s]) into out. extra_outage:
  /// an outage from the fault schedule (fault_schedule.hpp) at this tick.
  void sample(std::int64_t k, std::int64_t utime, const Quat& q_true, const Vec3& w_true, Attitude& out,
              bool extra_outage = false) noexcept {
    const double t = static_cast<double>(k) * T_;
    out.utime = utime;
    out.seq = k;
    sampleGyro(t, w_true, out);
    const bool outage = inOutage(t) || extra_outage;
    out.star_outage = outage ? 1 : 0;
    star_.take(k, outage, [&](double (&q)[4]) { measureStar(q_true, q); });
    out.star_valid = star_.deliver(k, outage) != nullptr ? 1 : 0;
    const Star::Sample& last = star_.last();
    out.star_time = last.t;
    for (int i = 0; i < 4; ++i) out.star_quaternion[i] = last.value[i];
  }

  const Vec3& gyroBias() const noexcept { return bias_; }  ///< b_k of the next tick [rad/s]

 private:
  using Star = SampleSchedule<4, SensorParams::kStarTrackerMaxLatencyPeriods>;

  bool inOutage(double t) const noexcept {
    const double tol = 1e-9 * T_;
    return outage_ && t >= p_.star_tracker_outage(0) - tol && t <= p_.star_tracker_outage(1) + tol;
  }

  void sampleGyro(double t, const Vec3& w_true, Attitude& out) noexcept {
    Vec3 w = w_true + bias_;
    if (p_.gyro_noise > 0.0) {
      for (int i = 0; i < 3; ++i) w(i) += p_.gyro_noise * gyro_noise_.normal();
    }
    if (p_.gyro_bias_walk > 0.0) {
      const double s = p_.gyro_bias_walk * std::sqrt(T_);
      for (int i = 0; i < 3; ++i) bias_(i) += s * gyro_noise_.normal();
    }
    out.gyro_time = t;
    for (int i = 0; i < 3; ++i) out.gyro_rate[i] = w(i);
  }

  /// The star tracker's quaternion (w x y z): q_true * dq, dq the rotation by N(0, noise^2) per base axis.
  void measureStar(const Quat& q_true, double (&out)[4]) noexcept {
    Quat q = q_true;
    if (p_.star_tracker_noise > 0.0) {
      Vec3 phi;
      for (int i = 0; i < 3; ++i) phi(i) = p_.star_tracker_noise * star_noise_.normal();
      const double angle = phi.norm();
      if (angle > 0.0) q = (q_true * Quat(Eigen::AngleAxisd(angle, phi / angle))).normalized();
    }
    out[0] = q.w(), out[1] = q.x(), out[2] = q.y(), out[3] = q.z();
  }

  SensorParams p_;
  double T_;
  GaussianNoise gyro_noise_, star_noise_;
  Vec3 bias_;
  Star star_;
  bool outage_;
};

}  // namespace gimbalsim::firmware
