#include "gimbalsim/firmware_sim/sensor_params.hpp"

#include <string>

namespace gimbalsim::firmware {
namespace {

/// 0 (off) or in [lo, hi]: a quantum below lo would make angle / quantum overflow.
Check zeroOr(double lo, double hi) {
  const std::string rule = "0 or in [" + formatNumber(lo) + ", " + formatNumber(hi) + "]";
  return {rule, "", [=](std::span<const double> v) {
            for (double x : v) {
              if (!(x == 0.0 || (x >= lo && x <= hi))) return false;
            }
            return true;
          }};
}

}  // namespace

// Every range is one the loop honours: no sensor value can overflow to Inf,
// and the star tracker's sample index stays far from int64's end (rate <= 1e6
// Hz and a run <= 1e9 s: j < 1e15).
std::vector<Key<SensorParams>> sensorKeys() {
  using K = Keys<SensorParams>;
  return {
      K::number("encoder_resolution", "rad", "firmware_sim: encoder quantum (0 = unquantized)",
                field(&SensorParams::encoder_resolution), zeroOr(1e-12, 1.0)),
      K::number("encoder_noise", "rad", "firmware_sim: Gaussian encoder noise sigma (0 = none)",
                field(&SensorParams::encoder_noise), interval('[', 0.0, 1.0, ']')),
      K::number("rate_noise", "rad/s", "firmware_sim: Gaussian rate noise sigma (0 = none)",
                field(&SensorParams::rate_noise), interval('[', 0.0, 100.0, ']')),
      K::integer("seed", "-",
                 "firmware_sim: sensor noise seed (encoders; the gyro and star tracker streams are derived from it)",
                 field(&SensorParams::seed), atLeast(0)),
      K::number("star_tracker_rate", "Hz",
                "star tracker sample rate; samples at multiples of its period (taken in the first control tick at "
                "or after)",
                field(&SensorParams::star_tracker_rate), interval('[', 1e-6, 1e6, ']')),
      K::number("star_tracker_noise", "rad",
                "star tracker noise: sigma per base axis of a small rotation applied to the quaternion (0 = none)",
                field(&SensorParams::star_tracker_noise), interval('[', 0.0, 1.0, ']')),
      K::number("star_tracker_latency", "s",
                "star tracker latency: a sample taken at t_s is delivered at the first tick at or after t_s + "
                "latency, stamped t_s; < 8 star tracker periods",
                field(&SensorParams::star_tracker_latency), interval('[', 0.0, 1e6, ']')),
      K::vector<2>("star_tracker_outage", "s",
                   "star tracker outage [start, end]: no sample taken or delivered, flagged ([0, 0] = none)",
                   field(&SensorParams::star_tracker_outage), interval('[', 0.0, 1e9, ']'), "[start, end]"),
      K::vector<3>("gyro_bias", "rad/s", "rate gyro constant bias, base frame",
                   field(&SensorParams::gyro_bias), interval('[', -1.0, 1.0, ']')),
      K::number("gyro_bias_walk", "rad/s/sqrt(s)", "rate gyro bias random walk sigma (0 = constant bias)",
                field(&SensorParams::gyro_bias_walk), interval('[', 0.0, 1.0, ']')),
      K::number("gyro_noise", "rad/s", "rate gyro white noise sigma per sample, each axis (0 = none)",
                field(&SensorParams::gyro_noise), interval('[', 0.0, 100.0, ']')),
      K::choice<bool>("antenna", "sensors on the antenna: none, or a boresight tracker and a rate gyro "
                      "(their own message, GIMBAL_ANTENNA; the default controller closes its loop at the antenna on them)",
                      field(&SensorParams::antenna_sensors), {{"none", false}, {"tracker_gyro", true}}),
      K::number("tracker_rate", "Hz", "boresight tracker sample rate (sensors.antenna tracker_gyro)",
                field(&SensorParams::tracker_rate), interval('[', 1e-3, 1e6, ']')),
      K::number("tracker_noise", "rad", "boresight tracker noise sigma per axis (0 = none)",
                field(&SensorParams::tracker_noise), interval('[', 0.0, 1.0, ']')),
      K::number("tracker_latency", "s",
                "boresight tracker latency: a sample taken at t_s is delivered at the first tick at or after t_s + "
                "latency, stamped t_s; < 8 tracker periods",
                field(&SensorParams::tracker_latency), interval('[', 0.0, 1e6, ']')),
      K::vector<2>("tracker_bias", "rad", "boresight tracker constant bias on its u (elevation axis) and v axes",
                   field(&SensorParams::tracker_bias), interval('[', -1.0, 1.0, ']'), "[u, v]"),
      K::vector<2>("tracker_outage", "s", "boresight tracker outage [start, end]: no sample, flagged ([0, 0] = none)",
                   field(&SensorParams::tracker_outage), interval('[', 0.0, 1e9, ']'), "[start, end]"),
      K::vector<3>("antenna_gyro_bias", "rad/s", "antenna rate gyro constant bias, antenna frame",
                   field(&SensorParams::antenna_gyro_bias), interval('[', -1.0, 1.0, ']')),
      K::number("antenna_gyro_noise", "rad/s", "antenna rate gyro white noise sigma per sample, each axis (0 = none)",
                field(&SensorParams::antenna_gyro_noise), interval('[', 0.0, 100.0, ']')),
  };
}

std::string starTrackerRedundant(const SensorParams& sp, bool floating_base, bool gyro_fault) {
  if (floating_base || gyro_fault || sp.star_tracker_noise > 0.0 || sp.gyro_noise > 0.0 || sp.gyro_bias_walk > 0.0 ||
      sp.gyro_bias.any()) {
    return "";
  }
  return "on a fixed base (scene key structure.base fixed) the star tracker reads the identity and the gyro, "
         "perfect (sensors.gyro_noise, gyro_bias, gyro_bias_walk 0), zero: with sensors.star_tracker_noise 0 an "
         "estimator propagates the attitude exactly without a star tracker sample";
}

void validateSensors(const SensorParams& sp, Given& g, const std::string& prefix) {
  if (!(sp.star_tracker_latency * sp.star_tracker_rate < SensorParams::kStarTrackerMaxLatencyPeriods)) {
    g.refuse(prefix + "star_tracker_latency",
             "must be < " + std::to_string(SensorParams::kStarTrackerMaxLatencyPeriods) +
                 " star tracker periods (" +
                 formatNumber(SensorParams::kStarTrackerMaxLatencyPeriods / sp.star_tracker_rate) + " s at " +
                 formatNumber(sp.star_tracker_rate) + " Hz)");
  }
  if (!(sp.tracker_latency * sp.tracker_rate < SensorParams::kStarTrackerMaxLatencyPeriods)) {
    g.refuse(prefix + "tracker_latency", "must be < " + std::to_string(SensorParams::kStarTrackerMaxLatencyPeriods) +
                                             " tracker periods (" +
                                             formatNumber(SensorParams::kStarTrackerMaxLatencyPeriods / sp.tracker_rate) +
                                             " s at " + formatNumber(sp.tracker_rate) + " Hz)");
  }
  // end > start, or [0, 0] for none: (pass 98) [0.2, 0.2] was none too, recorded as an outage and never flagged
  for (const auto& [name, w] : {std::pair{"tracker_outage", sp.tracker_outage},
                                std::pair{"star_tracker_outage", sp.star_tracker_outage}}) {
    if (!(w(1) > w(0) || (w(0) == 0.0 && w(1) == 0.0))) {
      g.refuse(prefix + name, "end must be > start ([0, 0] for none), got [" + formatNumber(w(0)) + ", " +
                                  formatNumber(w(1)) + "]");
    }
  }
}

}  // namespace gimbalsim::firmware
