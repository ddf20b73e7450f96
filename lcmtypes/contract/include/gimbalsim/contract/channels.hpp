// LCM channel names of one gimbal bench, shared by firmware_sim and
// pointing_controller. UPPER_SNAKE names; a prefix (e.g. "BENCH2_") lets
// several benches share one network: BENCH2_GIMBAL_COMMAND, ...
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <string>
#include <string_view>

namespace gimbalsim::contract {

struct Channels {
  static constexpr const char* kCommand = "GIMBAL_COMMAND";        ///< gimbal_command_t
  static constexpr const char* kStatus = "GIMBAL_STATUS";          ///< gimbal_status_t
  static constexpr const char* kTruth = "GIMBAL_TRUTH";            ///< gimbal_truth_t
  static constexpr const char* kLoopStats = "GIMBAL_LOOP_STATS";   ///< gimbal_loop_stats_t
  static constexpr const char* kAttitude = "GIMBAL_ATTITUDE";      ///< gimbal_attitude_t
  static constexpr const char* kAntenna = "GIMBAL_ANTENNA";        ///< gimbal_antenna_t (scenes with sensors.antenna)
  /// Every name above: what a prefix must leave within LCM's length.
  static constexpr std::array<const char*, 6> kNames = {kCommand, kStatus, kTruth, kLoopStats, kAttitude, kAntenna};

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

  /// LCM sends no channel name longer than this (LCM_MAX_CHANNEL_NAME_LENGTH): a longer one fails every publish.
  static constexpr std::size_t kMaxChannelName = 63;

  /// Why `prefix` cannot prefix the names ("" when it can): they stay UPPER_SNAKE (only A-Z, 0-9 and '_'),
  /// and each within LCM's length (pass 66: a 50-character prefix lost every command and attitude message).
  static std::string prefixProblem(const std::string& prefix) {
    if (!upperSnake(prefix)) return "only A-Z, 0-9 and '_' allowed (channel names are UPPER_SNAKE)";
    const std::string longest = *std::max_element(kNames.begin(), kNames.end(), [](const char* a, const char* b) {
      return std::string_view(a).size() < std::string_view(b).size();
    });
    if (prefix.size() + longest.size() > kMaxChannelName) {
      return "at most " + std::to_string(kMaxChannelName - longest.size()) +
             " characters: LCM names no channel longer than " + std::to_string(kMaxChannelName) + " (" + longest +
             " would have " + std::to_string(prefix.size() + longest.size()) + ")";
    }
    return "";
  }
  static bool validPrefix(const std::string& prefix) { return prefixProblem(prefix).empty(); }
  /// Only A-Z, 0-9 and '_' (a channel name that can also name a file).
  static bool upperSnake(const std::string& text) {
    for (char ch : text) {
      if (!((ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '_')) return false;
    }
    return true;
  }
};

}  // namespace gimbalsim::contract
