// Faults on purpose: a schedule of hardware faults the plant injects (a YAML
// file, fault_schedule_io.hpp; firmware_sim --faults, the in-process closed
// loop's ClosedLoopOptions::faults) and FaultClock, which turns the schedule
// into what is active at each tick. The firmware core (firmware.hpp) applies
// what FaultClock reports where each fault enters (README "Fault schedule",
// docs/ARCHITECTURE.md). FaultClock::at() is noexcept and allocation-free:
// every buffer is sized in the constructor.
//
// A fault is active at tick k (t_k = k T) when start <= t_k < end (to 1e-9 T)
// and, with probability p < 1, a uniform draw of its own seeded stream is
// below p (one draw per tick inside the window, so the same schedule and
// seed give the same ticks). bearing_wear and friction_rise ramp a bearing's
// parameter from the scene's value at start to the fault's at end and keep
// it: they stay active (flagged) from start on. They act on the bearing of
// their `axis`, or without one on every bearing with clearance, each from
// its own value.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "gimbalsim/dynamics/spatial.hpp"
#include "gimbalsim/firmware_sim/sensor_noise.hpp"

namespace gimbalsim::firmware {

/// The kinds of fault (the YAML `type:` names in faultTypeName()).
enum class FaultKind : std::uint8_t {
  EncoderDropout,     ///< axis: no new encoder sample: angle and rate repeat the last reported ones
  EncoderStuck,       ///< axis: the angle sticks at its value at onset; the rate sensor still works
  EncoderBias,        ///< axis: value [rad] added to the angle (a step)
  EncoderNoise,       ///< axis: Gaussian noise of sigma value [rad] added to the angle (a burst)
  StatusDelay,        ///< status messages delivered `ticks` ticks late
  StatusDrop,         ///< status messages not delivered
  CommandDelay,       ///< commands reach the firmware `ticks` ticks late
  CommandDrop,        ///< commands lost on the bus
  TorqueLimit,        ///< axis: motor limit reduced to value [N m]
  MotorFailure,       ///< axis: the motor gives zero torque (the firmware does not know)
  StarTrackerOutage,  ///< no star tracker sample taken or delivered, star_outage set
  GyroBiasJump,       ///< vector [rad/s] added to the gyro bias (a step), base frame
  BearingWear,        ///< axis or every clearance bearing: clearance grows from the scene's to value [m] over [start, end]
  FrictionRise,       ///< axis or every clearance bearing: mu rises from the scene's to value [-] over [start, end] (a step if end = start)
  TrackerOutage,      ///< the antenna's boresight tracker loses lock: no sample taken or delivered, tracker_outage set
  TrackerBias,        ///< bias [rad] (u, v) added to the tracker's reading (a step)
  TrackerDropout,     ///< the tracker's reading due this tick is lost (tracker_valid 0); the tracker still samples
};
inline constexpr int kNumFaultKinds = 17;

/// The YAML name of a kind ("encoder_dropout", ...).
const char* faultTypeName(FaultKind k);
/// Whether a kind acts on one axis (then `axis:` is required).
bool faultHasAxis(FaultKind k);
/// Whether a kind ramps a bearing's parameter (bearing_wear, friction_rise;
/// `axis:` optional: without it, every bearing with clearance).
inline bool faultIsRamp(FaultKind k) { return k == FaultKind::BearingWear || k == FaultKind::FrictionRise; }

/// The bit of a fault in the injected_faults mask of gimbal_status_t and
/// gimbal_truth_t: 1 << (2 kind + axis) (axis 0: azimuth, 1: elevation;
/// kinds without an axis use the even bit). 34 bits: the mask is 64-bit.
inline std::int64_t injectedBit(FaultKind k, int axis) noexcept {
  return std::int64_t{1} << (2 * static_cast<int>(k) + (axis == 1 ? 1 : 0));
}

inline constexpr double kForever = std::numeric_limits<double>::infinity();
/// Longest status or command delay [ticks] (the firmware's fixed queues).
inline constexpr int kMaxFaultDelayTicks = 1000;
/// Most entries in a schedule: every tick evaluates every entry, so the
/// count bounds the cost a schedule adds to a tick.
inline constexpr int kMaxFaults = 256;

/// One entry of a schedule.
struct FaultSpec {
  FaultKind kind = FaultKind::EncoderDropout;
  int axis = -1;              ///< 0 azimuth, 1 elevation; -1: none (ramps: every bearing with clearance)
  double start = 0.0;         ///< [s]
  double end = kForever;      ///< [s] (ramps: the end of the ramp)
  double probability = 1.0;   ///< per tick inside [start, end) [-]
  int ticks = 0;              ///< delays [ticks]
  double value = 0.0;         ///< bias or sigma [rad], torque limit [N m], clearance [m], mu [-]
  Vec3 vector = Vec3::Zero(); ///< gyro bias jump [rad/s]; tracker bias [rad] (u, v, 0)
  int line = 0;               ///< line in the schedule file (0: built in code)
  int column = 0;             ///< its column
  /// Where its axis and its parameter's value are written (line 0: not given), for the scene's checks.
  int axis_line = 0, axis_column = 0, param_line = 0, param_column = 0;
};

struct FaultSchedule {
  std::uint64_t seed = 1;        ///< seeds every probabilistic fault and every noise burst
  std::vector<FaultSpec> faults;
  bool empty() const noexcept { return faults.empty(); }
};

/// The first tick k (as a double) whose instant k T is at or after t [s], with FaultClock::at's tolerance
/// (1e-9 T): where a fault starting at t first acts, or where a sample due at t is taken or delivered.
inline double firstTickAtOrAfter(double t, double T) noexcept {
  return std::max(0.0, std::ceil((t - 1e-9 * T) / T));
}

/// What the faults active at one tick do (the sum of the active entries:
/// biases add, noise sigmas add in quadrature, limits take the lowest,
/// delays the longest; ramps take the last entry of their kind).
struct ActiveFaults {
  std::int64_t bits = 0;                 ///< injectedBit() of every active entry
  bool encoder_dropout[2] = {}, encoder_stuck[2] = {};
  double encoder_bias[2] = {};           ///< [rad]
  double encoder_noise[2] = {};          ///< this tick's noise sample [rad]
  int status_delay = 0;                  ///< [ticks]
  bool status_drop = false;
  int command_delay = 0;                 ///< [ticks]
  bool command_drop = false;
  double torque_limit[2] = {kForever, kForever};  ///< [N m]
  bool motor_failed[2] = {};
  bool star_outage = false;
  Vec3 gyro_bias = Vec3::Zero();         ///< [rad/s] added to the gyro
  double clearance[2] = {-1.0, -1.0};    ///< [m] bearing wear, per joint: the clearance now (< 0: the scene's)
  double mu[2] = {-1.0, -1.0};           ///< [-] friction rise, per joint: mu now (< 0: the scene's)
  bool tracker_outage = false, tracker_dropout = false;
  Vec2 tracker_bias = Vec2::Zero();      ///< [rad] added to the tracker's reading (u, v)
};

/// The schedule tick by tick. Call at(k) once per tick, k = 0, 1, 2, ...
class FaultClock {
 public:
  /// s may be null (no faults). clearance0, mu0: each joint's bearing in the
  /// scene (the ramps' starts); has_clearance: which joints have a bearing.
  FaultClock(const FaultSchedule* s, double control_period, const std::array<double, 2>& clearance0,
             const std::array<double, 2>& mu0, const std::array<bool, 2>& has_clearance)
      : s_(s), T_(control_period > 0.0 ? control_period : 1.0), clearance0_(clearance0), mu0_(mu0),
        has_clearance_(has_clearance) {
    if (s_ == nullptr) return;
    rng_.reserve(s_->faults.size());
    for (std::size_t i = 0; i < s_->faults.size(); ++i) rng_.emplace_back(streamSeed(s_->seed, 100 + i));
  }

  bool any() const noexcept { return s_ != nullptr && !s_->faults.empty(); }

  const ActiveFaults& at(std::int64_t k) noexcept {
    a_ = ActiveFaults{};
    if (!any()) return a_;
    const double t = static_cast<double>(k) * T_, tol = 1e-9 * T_;
    for (std::size_t i = 0; i < s_->faults.size(); ++i) {
      const FaultSpec& f = s_->faults[i];
      if (t < f.start - tol) continue;
      if (faultIsRamp(f.kind)) {
        const double span = f.end - f.start;
        const double x = span > tol ? std::clamp((t - f.start) / span, 0.0, 1.0) : 1.0;
        for (int j = 0; j < 2; ++j) {
          if (!(f.axis == j || (f.axis < 0 && has_clearance_[j]))) continue;
          if (f.kind == FaultKind::BearingWear) a_.clearance[j] = clearance0_[j] + x * (f.value - clearance0_[j]);
          if (f.kind == FaultKind::FrictionRise) a_.mu[j] = mu0_[j] + x * (f.value - mu0_[j]);
        }
        a_.bits |= injectedBit(f.kind, f.axis);
        continue;
      }
      if (t >= f.end - tol) continue;
      if (f.probability < 1.0 && !(rng_[i].uniform() <= f.probability)) continue;
      a_.bits |= injectedBit(f.kind, f.axis);
      const int j = f.axis == 1 ? 1 : 0;
      switch (f.kind) {
        case FaultKind::EncoderDropout: a_.encoder_dropout[j] = true; break;
        case FaultKind::EncoderStuck: a_.encoder_stuck[j] = true; break;
        case FaultKind::EncoderBias: a_.encoder_bias[j] += f.value; break;
        case FaultKind::EncoderNoise: {
          a_.encoder_noise[j] += f.value * rng_[i].normal();  // independent bursts: variances add
          break;
        }
        case FaultKind::StatusDelay: a_.status_delay = std::max(a_.status_delay, f.ticks); break;
        case FaultKind::StatusDrop: a_.status_drop = true; break;
        case FaultKind::CommandDelay: a_.command_delay = std::max(a_.command_delay, f.ticks); break;
        case FaultKind::CommandDrop: a_.command_drop = true; break;
        case FaultKind::TorqueLimit: a_.torque_limit[j] = std::min(a_.torque_limit[j], f.value); break;
        case FaultKind::MotorFailure: a_.motor_failed[j] = true; break;
        case FaultKind::StarTrackerOutage: a_.star_outage = true; break;
        case FaultKind::GyroBiasJump: a_.gyro_bias += f.vector; break;
        case FaultKind::TrackerOutage: a_.tracker_outage = true; break;
        case FaultKind::TrackerBias: a_.tracker_bias += f.vector.head<2>(); break;
        case FaultKind::TrackerDropout: a_.tracker_dropout = true; break;
        case FaultKind::BearingWear:
        case FaultKind::FrictionRise: break;  // handled above
      }
    }
    return a_;
  }

  const ActiveFaults& current() const noexcept { return a_; }

 private:
  const FaultSchedule* s_;
  double T_;
  std::array<double, 2> clearance0_, mu0_;
  std::array<bool, 2> has_clearance_;
  std::vector<GaussianNoise> rng_;  ///< one stream per entry (draws and noise)
  ActiveFaults a_;
};

}  // namespace gimbalsim::firmware
