// pointing_controller's choice of the plant it answers: which source's
// statuses it takes. One program's header, beside status_handler.hpp.
//
// The first source heard binds. Until the bound source has shown a plant's
// stream (a status whose seq follows its one before), the binding is
// provisional: another source's status takes it at once, so a stranger
// heard first (pass 78: a spoof with seq INT64_MAX every 10 ms held the
// controller for good) cannot keep a lockstep plant, which repeats status 0
// until it is answered, waiting. Once shown, another source takes over only
// when the bound one has been silent for kSilentNs (a restarted plant), or
// when it shows the stream itself (kStreak statuses with consecutive seq)
// while the bound one sent no consecutive status for kStalePeriods control
// periods (at least kMinStaleNs): a living plant never loses the controller.
// Sources are the kernel's (address, port): a process cannot pose as another
// socket; one that forges a whole consecutive stream is beyond what an
// unauthenticated bus can tell apart.
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
      : stale_ns_(std::max(kMinStaleNs,
                           static_cast<std::int64_t>(std::llround(kStalePeriods * control_period_s * 1e9)))) {}

  /// Whether a message from src is taken. has_seq: a decoded status, whose seq is seq. now_ns: CLOCK_MONOTONIC.
  /// A true return that binds another source than before is told by rebound() (the caller starts afresh).
  bool accept(lcm_wire::Source src, bool has_seq, std::int64_t seq, std::int64_t now_ns) noexcept {
    rebound_ = false;
    if (!bound_ || now_ns - heard_ns_ >= kSilentNs) {
      bindFresh(src, now_ns);
    } else if (!(src == plant_.src)) {
      if (!has_seq) {
        ++foreign_;
        return false;
      }
      const bool streak = noteCandidate(src, seq);
      if (plant_.shown && !(streak && now_ns - alive_ns_ >= stale_ns_)) {
        ++foreign_;
        return false;
      }
      takeCandidate(now_ns);
    }
    heard_ns_ = now_ns;
    if (has_seq) {
      if (follows(plant_.last_seq, seq)) {
        alive_ns_ = now_ns;
        plant_.shown = true;
      }
      plant_.last_seq = seq;
    }
    return true;
  }

  /// The bound source has sent a status that follows its one before: a plant's stream, not a lone status
  /// (pass 78's spoof, seq INT64_MAX, ended a controller's run as "past its last status").
  bool streamShown() const noexcept { return plant_.shown; }
  /// The last accept() bound a source other than the one bound before it.
  bool rebound() const noexcept { return rebound_; }
  /// Messages refused as from another source than the bound one.
  long long foreign() const noexcept { return foreign_; }
  /// Times another source took the binding from a bound one.
  long long rebinds() const noexcept { return rebinds_; }

 private:
  struct Sender {
    lcm_wire::Source src;
    std::int64_t last_seq = -1;  ///< its last status seq (-1: none)
    bool shown = false;          ///< one of its statuses followed the one before
    int streak = 0;              ///< its statuses in a row with consecutive seq (the candidate's)
  };

  /// seq is the one after prev (saturating: a seq of INT64_MAX has none after it).
  static bool follows(std::int64_t prev, std::int64_t seq) noexcept {
    return prev >= 0 && prev < std::numeric_limits<std::int64_t>::max() && seq == prev + 1;
  }

  /// Records src's status (before it is taken or refused); true when its streak shows a living plant.
  bool noteCandidate(lcm_wire::Source src, std::int64_t seq) noexcept {
    if (!(src == candidate_.src) || candidate_.streak == 0) candidate_ = Sender{src, -1, false, 0};
    candidate_.streak = follows(candidate_.last_seq, seq) ? candidate_.streak + 1 : 1;
    prev_candidate_seq_ = candidate_.last_seq;
    candidate_.last_seq = seq;
    return candidate_.streak >= kStreak;
  }

  /// The candidate becomes the plant with its history (its seq before this status, which accept() then
  /// judges); the plant it replaces becomes the candidate, so that a provisional binding flipped by a
  /// stranger's status is taken back on the plant's next one, already consecutive.
  void takeCandidate(std::int64_t now_ns) noexcept {
    Sender before = plant_;
    before.streak = before.last_seq >= 0 ? 1 : 0;
    plant_ = Sender{candidate_.src, prev_candidate_seq_, false, 0};
    candidate_ = before;
    alive_ns_ = now_ns;
    rebound_ = true;
    ++rebinds_;
  }

  void bindFresh(lcm_wire::Source src, std::int64_t now_ns) noexcept {
    rebound_ = bound_ && !(src == plant_.src);
    if (rebound_) ++rebinds_;
    bound_ = true;
    plant_ = Sender{src, -1, false, 0};
    candidate_ = Sender{};
    alive_ns_ = now_ns;  // a fresh binding is alive until it fails to show a stream
  }

  std::int64_t stale_ns_;
  bool bound_ = false, rebound_ = false;
  Sender plant_, candidate_;
  std::int64_t prev_candidate_seq_ = -1;
  std::int64_t heard_ns_ = 0, alive_ns_ = 0;  ///< [ns] last message of the bound source; its last consecutive status
  long long foreign_ = 0, rebinds_ = 0;
};

}  // namespace gimbalsim::controllers
