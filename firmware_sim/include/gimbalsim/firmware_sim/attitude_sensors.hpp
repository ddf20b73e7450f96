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
//  - star tracker: sample j belongs to the instant j P (P = 1 / rate) and is
//    taken in the first tick at or after it (t_s = t_k; = j P exactly when P
//    is a whole multiple of T); at most one sample per tick. Its quaternion
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
#include "gimbalsim/firmware_sim/sensor_noise.hpp"

namespace gimbalsim::firmware {
// The bench messages are the contract's (lcmtypes/contract), shared with the controller.
using namespace gimbalsim::contract;  // NOLINT(google-build-using-namespace)

/// Sensor streams derived from sensors.seed (streamSeed); the encoders use the seed itself.
enum SensorStream : std::uint64_t { kGyroStream = 1, kStarTrackerStream = 2 };

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
        latency_ticks_(ticksAtOrAfter(p.star_tracker_latency)),
        outage_(p.star_tracker_outage(1) > p.star_tracker_outage(0)) {
    if (!(p_.star_tracker_rate > 0.0)) p_.star_tracker_rate = 1.0 / T_;
  }

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
    out.star_valid = 0;
    if (k >= next_tick_) {
      if (!outage) push(k, t, q_true);
      advanceSampleIndex(k);
    }
    // Deliver the newest sample due (drop older ones due, and all of them in an outage).
    const Pending* due = nullptr;
    while (count_ > 0 && ring_[head_].deliver_tick <= k) {
      due = &ring_[head_];
      head_ = (head_ + 1) % kCapacity;
      --count_;
    }
    if (due != nullptr && !outage) {
      out.star_valid = 1;
      last_ = *due;
    }
    out.star_time = last_.t;
    for (int i = 0; i < 4; ++i) out.star_quaternion[i] = last_.q[i];
  }

  const Vec3& gyroBias() const noexcept { return bias_; }  ///< b_k of the next tick [rad/s]

 private:
  struct Pending {
    std::int64_t deliver_tick = 0;
    double t = 0.0;
    double q[4] = {1.0, 0.0, 0.0, 0.0};
  };
  /// Samples in flight: latency < kStarTrackerMaxLatencyPeriods periods and
  /// samples at least max(P - T, T) apart keep fewer than this queued.
  static constexpr int kCapacity = 4 * SensorParams::kStarTrackerMaxLatencyPeriods;

  /// Ticks from 0 to the first tick at or after time x [s].
  std::int64_t ticksAtOrAfter(double x) const noexcept {
    const double k = std::ceil(x / T_ - 1e-9);
    return k < 4e18 ? static_cast<std::int64_t>(k) : std::int64_t{4000000000000000000};
  }
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

  void push(std::int64_t k, double t, const Quat& q_true) noexcept {
    Quat q = q_true;
    if (p_.star_tracker_noise > 0.0) {
      Vec3 phi;
      for (int i = 0; i < 3; ++i) phi(i) = p_.star_tracker_noise * star_noise_.normal();
      const double angle = phi.norm();
      if (angle > 0.0) q = (q_true * Quat(Eigen::AngleAxisd(angle, phi / angle))).normalized();
    }
    if (count_ == kCapacity) {  // cannot happen within the latency limit; keep the newest
      head_ = (head_ + 1) % kCapacity;
      --count_;
    }
    Pending& p = ring_[(head_ + count_) % kCapacity];
    p.deliver_tick = k + latency_ticks_;
    p.t = t;
    p.q[0] = q.w(), p.q[1] = q.x(), p.q[2] = q.y(), p.q[3] = q.z();
    ++count_;
  }

  /// The next sample index j whose tick is after k. The index jumps straight
  /// to the first instant after t_k (no count one by one: at a rate far above
  /// the control rate that would be ~rate x T steps per tick), clamped below
  /// int64's end; the loop then only steps over rounding, a bounded few times.
  void advanceSampleIndex(std::int64_t k) noexcept {
    const double P = 1.0 / p_.star_tracker_rate;
    const double t = static_cast<double>(k) * T_;
    const double j = std::min(std::floor(t / P), 4e18);
    next_j_ = std::max(next_j_ + 1, static_cast<std::int64_t>(j));
    for (int i = 0; i < kMaxIndexSteps && (next_tick_ = ticksAtOrAfter(static_cast<double>(next_j_) * P)) <= k; ++i) {
      ++next_j_;
    }
    if (next_tick_ <= k) next_tick_ = k + 1;  // P below double's resolution at t: one sample per tick
  }
  static constexpr int kMaxIndexSteps = 4;  ///< floor(t / P) is off by at most one or two in rounding

  SensorParams p_;
  double T_;
  GaussianNoise gyro_noise_, star_noise_;
  Vec3 bias_;
  std::int64_t latency_ticks_;
  bool outage_;
  std::int64_t next_j_ = 0;     ///< index of the next star tracker sample
  std::int64_t next_tick_ = 0;  ///< the tick that takes it
  Pending ring_[kCapacity];
  Pending last_{0, -1.0, {1.0, 0.0, 0.0, 0.0}};  ///< the last sample delivered (t = -1: none yet)
  int head_ = 0, count_ = 0;
};

}  // namespace gimbalsim::firmware
