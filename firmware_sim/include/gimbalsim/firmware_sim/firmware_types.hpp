// The firmware's settings, counters and refusal reasons (firmware.hpp runs
// them): what firmware_sim's options, summaries and tests name.
#pragma once

#include <cstdint>
#include <string>

#include "gimbalsim/dynamics/run_spec.hpp"
#include "gimbalsim/firmware_sim/fault_bus.hpp"

namespace gimbalsim::firmware {

/// Firmware settings that are not part of the scene (command-line options).
struct Config {
  double control_period = 1.0e-3;     ///< T [s], a whole multiple of sim.step
  double watchdog_timeout = 0.05;     ///< no valid command for this long -> safe command [s]
  double torque_sanity_factor = 10.0; ///< reject |torque| > factor * torque.limit [-]
  Vec2 safe_torque = Vec2::Zero();    ///< applied while the watchdog is tripped [N m]
};

/// Why a command was refused.
enum class Rejection : std::uint8_t {
  None,
  NonFinite,     ///< NaN or Inf torque
  OutOfRange,    ///< |torque| beyond the sanity range
  UnknownMode,   ///< mode not OFF or TORQUE
  StaleSeq,      ///< seq <= the last seq accepted from the bound source (stale or duplicate)
  FutureStatus,  ///< answers a status not yet published
  Undecodable,   ///< bytes that are not a gimbal_command_t
  WrongSource,   ///< from another source than the one bound (command_gate.hpp)
};
inline constexpr int kNumRejections = 8;
const char* describe(Rejection r);

/// Counters kept by the firmware (cumulative).
struct Counters {
  std::int64_t received = 0;    ///< command messages, garbage included
  std::int64_t rejected = 0;    ///< all rejections
  std::int64_t missed = 0;      ///< ticks (k >= 1) without a new valid command
  std::int64_t by_reason[kNumRejections] = {};  ///< rejections per Rejection
  std::int64_t watchdog_trips = 0;   ///< transitions into the tripped state
  std::int64_t motor_limited_ticks = 0;  ///< ticks whose applied torque the motor limit (torque.limit) clipped
  std::int64_t substeps = 0;         ///< RK4 evaluations, all ticks
  int max_substeps_in_tick = 0;
  /// The most forward-dynamics evaluations one tick's stepping took (the count the worst-case bound bounds).
  long long max_derivatives_in_tick = 0;
  BusFaultCounts bus;                ///< scheduled faults on the bus and the status channel (fault_bus.hpp)
  std::int64_t fault_ticks = 0;      ///< ticks with any scheduled fault active
};

/// The most frequent reason among the rejections counted between `before`
/// and `now` (cumulative counters); Rejection::None when there were none.
Rejection commonestRejection(const Counters& before, const Counters& now) noexcept;

/// Result of checkConfig(): which setting is wrong (a code the caller maps to
/// its option, e.g. firmware_sim's --rate), and the text saying why.
struct ConfigCheck {
  enum class Setting : std::uint8_t {
    None,                ///< fine
    ControlPeriod,       ///< not > 0, or not a whole multiple of sim.step
    WatchdogTimeout,     ///< not > 0
    TorqueSanityFactor,  ///< not >= 1
    SafeTorque,          ///< not finite or beyond torque.limit
  };
  Setting wrong = Setting::None;
  std::string message;     ///< empty when fine
  int steps_per_tick = 0;  ///< T / sim.step when fine

  bool ok() const noexcept { return wrong == Setting::None; }
};

/// Checks a Config against a scene.
ConfigCheck checkConfig(const Scene& sc, const Config& c);

}  // namespace gimbalsim::firmware
