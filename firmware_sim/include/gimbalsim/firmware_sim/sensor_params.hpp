// The gimbal's sensors as the firmware reports them: encoders, rate
// sensors, star tracker and rate gyro. Owned by the plant (firmware_sim):
// the scene file's sensors.* keys, read by loadPlantScene (plant_scene.hpp).
#pragma once

#include <string>
#include <vector>

#include "gimbalsim/dynamics/spatial.hpp"
#include "gimbalsim/input/key_registry.hpp"

namespace gimbalsim::firmware {

/// Sensors as the gimbal firmware reports them (firmware_sim and the closed loop).
struct SensorParams {
  double encoder_resolution = 5.992112452678286e-6;  ///< 2 pi / 2^20 [rad]; 0 = unquantized
  double encoder_noise = 0.0;   ///< Gaussian encoder noise sigma, before quantization [rad]
  double rate_noise = 0.0;      ///< Gaussian rate noise sigma [rad/s]
  long long seed = 1;           ///< noise generator seed (>= 0); one stream per sensor is derived from it

  // Attitude sensors (attitude_sensors.hpp). The defaults are perfect
  // sensors: no noise, no bias, no latency, no outage.
  double star_tracker_rate = 10.0;     ///< star tracker sample rate [Hz], > 0
  double star_tracker_noise = 0.0;     ///< small-rotation noise sigma per base axis [rad]
  double star_tracker_latency = 0.0;   ///< sample at t_s delivered at t_s + latency [s], < kStarTrackerMaxLatencyPeriods / rate
  Vec2 star_tracker_outage = Vec2::Zero();  ///< [start, end] [s] without star tracker samples; end <= start = none
  Vec3 gyro_bias = Vec3::Zero();       ///< constant rate gyro bias, base frame [rad/s]
  double gyro_bias_walk = 0.0;         ///< bias random walk sigma [rad/s/sqrt(s)]
  double gyro_noise = 0.0;             ///< white rate noise sigma per sample [rad/s]

  // Antenna sensors (antenna_sensors.hpp): none unless the scene names them.
  bool antenna_sensors = false;        ///< sensors.antenna: none | tracker_gyro
  double tracker_rate = 1000.0;        ///< boresight tracker sample rate [Hz], > 0
  double tracker_noise = 0.0;          ///< tracker noise sigma per axis [rad]
  double tracker_latency = 0.0;        ///< sample at t_s delivered at t_s + latency [s], < kStarTrackerMaxLatencyPeriods / rate
  Vec2 tracker_bias = Vec2::Zero();    ///< constant tracker bias on its u, v axes [rad]
  Vec2 tracker_outage = Vec2::Zero();  ///< [start, end] [s] without tracker samples; end <= start = none
  Vec3 antenna_gyro_bias = Vec3::Zero();  ///< antenna rate gyro bias, antenna frame [rad/s]
  double antenna_gyro_noise = 0.0;     ///< antenna rate gyro white noise sigma per sample [rad/s]

  /// Whether any sensor draws noise (what sensors.seed seeds); a fault schedule's bursts have their own seed.
  bool anyNoise() const {
    return encoder_noise > 0.0 || rate_noise > 0.0 || star_tracker_noise > 0.0 || gyro_bias_walk > 0.0 ||
           gyro_noise > 0.0 || (antenna_sensors && (tracker_noise > 0.0 || antenna_gyro_noise > 0.0));
  }

  /// Longest star tracker (and boresight tracker) latency, in its own periods (fixed queue of samples in flight).
  static constexpr int kStarTrackerMaxLatencyPeriods = 8;
};

/// The sensors.* keys (without the prefix), bound to SensorParams.
std::vector<Key<SensorParams>> sensorKeys();

/// Why the star tracker tells an estimator nothing, or "" when it can: on a fixed base (floating_base false) it
/// reads the identity and a perfect gyro (no noise, bias or bias walk; gyro_fault false: no fault schedule's
/// gyro_bias_jump) reads zero, so without star tracker noise the attitude propagates exactly without it (pass 89).
std::string starTrackerRedundant(const SensorParams& sp, bool floating_base, bool gyro_fault);

/// Checks across the sensor keys (each key has passed its own check); names keys with `prefix`.
void validateSensors(const SensorParams& sp, Given& g, const std::string& prefix);

}  // namespace gimbalsim::firmware
