// The joint encoders and rate sensors the status reports: noise before
// quantization, and the encoder faults (bias, noise, stuck, dropout).
// docs/MODEL.md Section 11; docs/bench.md "Faults" for the fault kinds.
#pragma once

#include <cmath>
#include <cstdint>

#include "gimbalsim/contract/messages.hpp"
#include "gimbalsim/firmware_sim/fault_schedule.hpp"
#include "gimbalsim/firmware_sim/sensor_noise.hpp"
#include "gimbalsim/firmware_sim/sensor_params.hpp"

namespace gimbalsim::firmware {

/// Encoder quantization: the multiple of `resolution` nearest to x (x itself if resolution is 0).
inline double quantize(double x, double resolution) noexcept {
  return resolution > 0.0 ? resolution * std::nearbyint(x / resolution) : x;
}

/// What the joint sensors remember between ticks: a stuck encoder's angle and
/// the last sample (a dropout repeats it). Allocation-free.
class JointSensors {
 public:
  /// The joint angles [rad] and rates [rad/s] of state s at tick k into
  /// o.angle and o.rate; noise draws in joint order, encoder before rate.
  template <class State>
  void sample(std::int64_t k, const State& s, const SensorParams& sp, const ActiveFaults& af, GaussianNoise& noise,
              contract::Status& o) noexcept {
    for (int j = 0; j < 2; ++j) {
      double a = s.theta(j), w = s.dtheta(j);
      if (sp.encoder_noise > 0.0) a += sp.encoder_noise * noise.normal();
      if (sp.rate_noise > 0.0) w += sp.rate_noise * noise.normal();
      o.angle[j] = quantize(a + af.encoder_bias[j] + af.encoder_noise[j], sp.encoder_resolution);
      o.rate[j] = w;
      if (af.encoder_stuck[j]) {  // the angle sticks where it was at onset; the rate sensor still works
        if (!stuck_[j]) stuck_angle_[j] = o.angle[j];
        o.angle[j] = stuck_angle_[j];
      }
      stuck_[j] = af.encoder_stuck[j];
      if (af.encoder_dropout[j] && k > 0) {  // no new sample: the last one again
        o.angle[j] = last_angle_[j];
        o.rate[j] = last_rate_[j];
      }
      last_angle_[j] = o.angle[j];
      last_rate_[j] = o.rate[j];
    }
  }

 private:
  bool stuck_[2] = {};
  double stuck_angle_[2] = {}, last_angle_[2] = {}, last_rate_[2] = {};  ///< [rad], [rad], [rad/s]
};

}  // namespace gimbalsim::firmware
