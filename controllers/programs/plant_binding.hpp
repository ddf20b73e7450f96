// pointing_controller's choice of the plant it answers: which source's
// statuses it takes. One program's header, beside status_handler.hpp.
//
// The first source heard binds. Another takes over when the bound one has
// been silent for kSilentNs (a restarted plant), or when it shows the stream a
// living plant sends (kStreak statuses with consecutive seq) while the bound
// source sent no consecutive status for kStalePeriods control periods (at
// least kMinStaleNs): a stranger whose status arrived first (pass 78: a spoof
// with seq INT64_MAX every 10 ms held the controller for good) loses it to
// the plant, and a living plant, whose every status follows the last, never
// loses it. Sources are the kernel's (address, port): a process cannot pose
// as another socket; one that forges a whole consecutive stream is beyond
// what an unauthenticated bus can tell apart.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "gimbalsim/lcm_wire/udpm_reassembler.hpp"

namespace gimbalsim::controllers {

class PlantBinding {
 public:
  static constexpr std::int64_t kSilentNs = 500000000;  ///< bound source silent this long -> any may bind [ns]
  static constexpr int kStreak = 10;                    ///< consecutive statuses that show a living plant
  static constexpr int kStalePeriods = 5;               ///< bound source without a consecutive status this long
  static constexpr std::int64_t kMinStaleNs = 20000000; ///< ... and at least this long [ns]

  /// control_period_s: the controller's period [s], the interval of a real-time plant's statuses.
  explicit PlantBinding(double control_period_s)
      : stale_ns_(std::max(kMinStaleNs, static_cast<std::int64_t>(std::llround(kStalePeriods * control_period_s * 1e9)))) {}

  /// Whether a message from src is taken. has_seq: a decoded status, whose seq is seq. now_ns: CLOCK_MONOTONIC.
  /// A true return that binds another source than before is told by rebound() (the caller starts afresh).
  bool accept(lcm_wire::Source src, bool has_seq, std::int64_t seq, std::int64_t now_ns) noexcept {
    rebound_ = false;
    if (!bound_ || now_ns - heard_ns_ >= kSilentNs) {
      bind(src, now_ns);
    } else if (!(src == plant_)) {
      if (!has_seq || !livingStream(src, seq, now_ns)) {
        ++foreign_;
        return false;
      }
      bind(src, now_ns);
    }
    heard_ns_ = now_ns;
    if (has_seq) {
      if (follows(last_seq_, seq)) {
        alive_ns_ = now_ns;
        stream_shown_ = true;
      }
      last_seq_ = seq;
    }
    return true;
  }

  /// The bound source has sent a status that follows its one before (since it was bound): a plant's stream,
  /// not a lone status (pass 78's spoof, seq INT64_MAX, ended a controller's run as "past its last status").
  bool streamShown() const noexcept { return stream_shown_; }
  /// The last accept() bound a source other than the one bound before it.
  bool rebound() const noexcept { return rebound_; }
  /// Messages refused as from another source than the bound one.
  long long foreign() const noexcept { return foreign_; }
  /// Times another source took the binding from a bound one.
  long long rebinds() const noexcept { return rebinds_; }

 private:
  /// seq is the one after prev (saturating: a seq of INT64_MAX has none after it).
  static bool follows(std::int64_t prev, std::int64_t seq) noexcept {
    return prev >= 0 && prev < std::numeric_limits<std::int64_t>::max() && seq == prev + 1;
  }

  /// The candidate src's streak of consecutive statuses, with this one; true when it shows a living plant
  /// and the bound source has shown none for the stale span.
  bool livingStream(lcm_wire::Source src, std::int64_t seq, std::int64_t now_ns) noexcept {
    if (src == candidate_ && streak_ > 0 && follows(candidate_seq_, seq)) {
      ++streak_;
    } else {
      candidate_ = src;
      streak_ = 1;
    }
    candidate_seq_ = seq;
    return streak_ >= kStreak && now_ns - alive_ns_ >= stale_ns_;
  }

  void bind(lcm_wire::Source src, std::int64_t now_ns) noexcept {
    rebound_ = bound_ && !(src == plant_);
    if (rebound_) ++rebinds_;
    bound_ = true;
    plant_ = src;
    alive_ns_ = now_ns;  // a fresh binding is alive until it fails to show a stream
    last_seq_ = -1;
    stream_shown_ = false;
    streak_ = 0;
  }

  std::int64_t stale_ns_;
  bool bound_ = false, rebound_ = false, stream_shown_ = false;
  lcm_wire::Source plant_, candidate_;
  std::int64_t heard_ns_ = 0, alive_ns_ = 0;  ///< [ns] last message of the bound source; its last consecutive status
  std::int64_t last_seq_ = -1;                ///< the bound source's last status seq (-1: none since binding)
  std::int64_t candidate_seq_ = -1;
  int streak_ = 0;
  long long foreign_ = 0, rebinds_ = 0;
};

}  // namespace gimbalsim::controllers
