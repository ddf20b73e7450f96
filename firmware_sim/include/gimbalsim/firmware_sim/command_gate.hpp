// Who may command the plant, and in which order: the part of command
// acceptance that no single spoofed packet can subvert. The first command
// that passes every check binds the gate to its source (sender address:port,
// as the kernel reports it; in process: kInProcessSource). While bound,
// commands from any other source are refused (WrongSource) and seq is checked
// against the bound source's own history only, so a stranger's seq, however
// extreme, is never recorded. The binding lasts until the watchdog has
// tripped (no command accepted for more than `binding_ticks`): then the next valid
// command binds afresh, with a fresh seq history, so even an extreme seq from
// the bound source locks nobody out for longer than the watchdog. A refused
// command changes nothing here. Ticks and seqs are int64: comparisons only,
// no arithmetic that can overflow.
#pragma once

#include <cstdint>

namespace gimbalsim::firmware {

/// A command's sender: lcm_wire::Source::id() over the network.
using SourceId = std::uint64_t;
inline constexpr SourceId kInProcessSource = 0;

class CommandGate {
 public:
  enum class Verdict : std::uint8_t { Accept, WrongSource, StaleSeq };

  explicit CommandGate(std::int64_t binding_ticks) noexcept : binding_ticks_(binding_ticks) {}

  /// Would a command (seq) from `src`, arriving before tick `tick` (the index
  /// of the next tick), be accepted? Changes nothing.
  Verdict check(SourceId src, std::int64_t seq, std::int64_t tick) const noexcept {
    // Command accepted before tick a acts from tick a; the watchdog trips at
    // tick a + binding_ticks; from the next tick on, the binding is over.
    const bool live = bound_ && tick - accepted_tick_ <= binding_ticks_;
    if (live && src != source_) return Verdict::WrongSource;
    const std::int64_t last = live ? last_seq_ : -1;  // a new binding starts a fresh history
    return seq <= last ? Verdict::StaleSeq : Verdict::Accept;
  }

  /// Records an accepted command (after check() said Accept and every other check passed).
  void accept(SourceId src, std::int64_t seq, std::int64_t tick) noexcept {
    bound_ = true;
    source_ = src;
    last_seq_ = seq;
    accepted_tick_ = tick;
  }

  /// Ends the binding as a watchdog trip does: the next valid command binds afresh. For lockstep, whose
  /// watchdog counts ticks that each wait --lockstep-timeout-ms: a bound controller that has gone while
  /// another answers (restarted) would otherwise hold the plant past --start-timeout.
  void release() noexcept { bound_ = false; }

  bool bound() const noexcept { return bound_; }
  SourceId source() const noexcept { return source_; }
  std::int64_t lastSeq() const noexcept { return bound_ ? last_seq_ : -1; }
  std::int64_t bindingTicks() const noexcept { return binding_ticks_; }

 private:
  std::int64_t binding_ticks_;
  bool bound_ = false;
  SourceId source_ = kInProcessSource;
  std::int64_t last_seq_ = -1;
  std::int64_t accepted_tick_ = 0;
};

}  // namespace gimbalsim::firmware
