// LCM channel names of one gimbal bench, shared by firmware_sim and
// pointing_controller. UPPER_SNAKE names; a prefix (e.g. "BENCH2_") lets
// several benches share one network: BENCH2_GIMBAL_COMMAND, ...
#pragma once

#include <string>

namespace gimbalsim::contract {

struct Channels {
  static constexpr const char* kCommand = "GIMBAL_COMMAND";        ///< gimbal_command_t
  static constexpr const char* kStatus = "GIMBAL_STATUS";          ///< gimbal_status_t
  static constexpr const char* kTruth = "GIMBAL_TRUTH";            ///< gimbal_truth_t
  static constexpr const char* kLoopStats = "GIMBAL_LOOP_STATS";   ///< gimbal_loop_stats_t
  static constexpr const char* kAttitude = "GIMBAL_ATTITUDE";      ///< gimbal_attitude_t
  static constexpr const char* kAntenna = "GIMBAL_ANTENNA";        ///< gimbal_antenna_t (scenes with sensors.antenna)

  std::string command = kCommand;
  std::string status = kStatus;
  std::string truth = kTruth;
  std::string loop_stats = kLoopStats;
  std::string attitude = kAttitude;
  std::string antenna = kAntenna;

  /// The names with `prefix` in front (empty prefix: the plain names).
  static Channels withPrefix(const std::string& prefix) {
    Channels c;
    c.command = prefix + kCommand;
    c.status = prefix + kStatus;
    c.truth = prefix + kTruth;
    c.loop_stats = prefix + kLoopStats;
    c.attitude = prefix + kAttitude;
    c.antenna = prefix + kAntenna;
    return c;
  }

  /// A prefix keeps the names UPPER_SNAKE: only A-Z, 0-9 and '_'.
  static bool validPrefix(const std::string& prefix) {
    for (char ch : prefix) {
      const bool ok = (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_';
      if (!ok) return false;
    }
    return true;
  }
};

}  // namespace gimbalsim::contract
