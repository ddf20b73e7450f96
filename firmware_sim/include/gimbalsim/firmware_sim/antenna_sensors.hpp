// The antenna's own sensors (scene key sensors.antenna: tracker_gyro): a
// two-axis boresight tracker and a rate gyro on the antenna. They see what
// no encoder can: where the antenna itself points, play and tilt included.
// Seeded and deterministic as the attitude sensors; sample() is noexcept and
// allocation-free. A scene without them has no AntennaSensors at all.
//
// Tick k at t_k = k T:
//  - tracker, on its schedule (sample_schedule.hpp, rate and latency): the
//    reading of pointing/tracker_axes.hpp (the rotation taking the boresight
//    onto the target, on the antenna's u, v axes) + bias + N(0, noise^2) per axis. Outage [start, end]
//    (sensors.tracker_outage, or the fault schedule): no sample taken or
//    delivered, tracker_outage set; between deliveries the message holds the
//    last sample with tracker_valid = 0 (tracker_time = -1 before the first).
//  - gyro, every tick: the antenna's angular velocity in its own frame, plus
//    bias and N(0, noise^2) per axis.
#pragma once

#include <cstdint>

#include "gimbalsim/contract/messages.hpp"
#include "gimbalsim/dynamics/model.hpp"
#include "gimbalsim/firmware_sim/attitude_sensors.hpp"
#include "gimbalsim/firmware_sim/sample_schedule.hpp"
#include "gimbalsim/firmware_sim/sensor_noise.hpp"
#include "gimbalsim/firmware_sim/sensor_params.hpp"
#include "gimbalsim/pointing/tracker_axes.hpp"

namespace gimbalsim::firmware {

class AntennaSensors {
 public:
  /// p must pass the scene checks; control_period > 0.
  AntennaSensors(const Model& m, const SensorParams& p, double control_period) noexcept
      : p_(p),
        T_(control_period > 0.0 ? control_period : 1.0),
        axes_(pointing::trackerAxes(m.k2_S1, m.boresight_S2)),
        tracker_noise_(streamSeed(static_cast<std::uint64_t>(p.seed), kTrackerStream)),
        gyro_noise_(streamSeed(static_cast<std::uint64_t>(p.seed), kAntennaGyroStream)),
        tracker_(p.tracker_rate, p.tracker_latency, T_, Tracker::Sample{}),
        outage_(p.tracker_outage(1) > p.tracker_outage(0)) {}

  /// Measures tick k from the antenna's attitude R_WA (antenna -> inertial),
  /// its angular velocity w_A (antenna frame [rad/s]) and the target's line
  /// of sight target_W (unit, inertial). Fault-schedule effects: extra_outage
  /// (no sample), extra_bias [rad] added to the reading, dropout (this tick's
  /// delivery lost).
  void sample(std::int64_t k, std::int64_t utime, const Mat3& R_WA, const Vec3& w_A, const Vec3& target_W,
              contract::Antenna& out, bool extra_outage = false, const Vec2& extra_bias = Vec2::Zero(),
              bool dropout = false) noexcept {
    const double t = static_cast<double>(k) * T_;
    out.utime = utime;
    out.seq = k;
    const bool outage = inOutage(t) || extra_outage;
    out.tracker_outage = outage ? 1 : 0;
    tracker_.take(k, outage, [&](double (&m)[2]) {
      const Vec2 r = pointing::trackerReading(axes_, R_WA, target_W) + p_.tracker_bias + extra_bias;
      for (int i = 0; i < 2; ++i) {
        m[i] = r(i) + (p_.tracker_noise > 0.0 ? p_.tracker_noise * tracker_noise_.normal() : 0.0);
      }
    });
    out.tracker_valid = tracker_.deliver(k, outage || dropout) != nullptr ? 1 : 0;  // a dropout loses what fell due
    const Tracker::Sample& last = tracker_.last();
    out.tracker_time = last.t;
    out.tracker_error[0] = last.value[0], out.tracker_error[1] = last.value[1];
    Vec3 w = w_A + p_.antenna_gyro_bias;
    if (p_.antenna_gyro_noise > 0.0) {
      for (int i = 0; i < 3; ++i) w(i) += p_.antenna_gyro_noise * gyro_noise_.normal();
    }
    out.gyro_time = t;
    for (int i = 0; i < 3; ++i) out.gyro_rate[i] = w(i);
  }

 private:
  using Tracker = SampleSchedule<2, SensorParams::kStarTrackerMaxLatencyPeriods>;

  bool inOutage(double t) const noexcept {
    const double tol = 1e-9 * T_;
    return outage_ && t >= p_.tracker_outage(0) - tol && t <= p_.tracker_outage(1) + tol;
  }

  SensorParams p_;
  double T_;
  pointing::TrackerAxes axes_;
  GaussianNoise tracker_noise_, gyro_noise_;
  Tracker tracker_;
  bool outage_;
};

}  // namespace gimbalsim::firmware
