// The field bus between the controller and the firmware under scheduled bus
// faults (fault_schedule.hpp): commands lost or held for a delay on their way
// in, statuses dropped or delayed on their way out. Both directions are FIFOs
// (a bus keeps order); a held message is never due before the ones ahead of
// it. Rings sized once at construction, so no call allocates; without a
// schedule every call passes its message straight through.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "gimbalsim/firmware_sim/command_gate.hpp"
#include "gimbalsim/firmware_sim/fault_schedule.hpp"
#include "gimbalsim/contract/messages.hpp"

namespace gimbalsim::firmware {
// The bench messages are the contract's (lcmtypes/contract), shared with the controller.
using namespace gimbalsim::contract;  // NOLINT(google-build-using-namespace)

/// What the bus faults did (cumulative).
struct BusFaultCounts {
  std::int64_t commands_dropped = 0, commands_delayed = 0;
  std::int64_t status_dropped = 0, status_delayed = 0;
};

class FaultBus {
 public:
  /// `faults_scheduled`: false when no fault can ever be active (then nothing is held).
  explicit FaultBus(bool faults_scheduled) : enabled_(faults_scheduled) {
    if (enabled_) {
      statuses_.resize(kMaxFaultDelayTicks + 2);
      commands_.resize(4 * (kMaxFaultDelayTicks + 2));
    }
  }

  /// A command arriving before tick `tick`: true when the bus took it (lost,
  /// or held for the delay), false to pass it on now.
  bool take(const Command& cmd, SourceId src, std::int64_t tick, const ActiveFaults& af, BusFaultCounts& n) noexcept {
    if (!enabled_ || releasing_) return false;
    if (af.command_drop) {
      ++n.commands_dropped;
      return true;
    }
    if (af.command_delay <= 0 && cmd_count_ == 0) return false;
    if (cmd_count_ == commands_.size()) {  // full: the oldest is lost
      cmd_head_ = (cmd_head_ + 1) % commands_.size();
      --cmd_count_;
      ++n.commands_dropped;
    }
    // Behind the ones held, in order, never due before them.
    std::int64_t due = tick + af.command_delay;
    if (cmd_count_ > 0) due = std::max(due, commands_[(cmd_head_ + cmd_count_ - 1) % commands_.size()].due);
    commands_[(cmd_head_ + cmd_count_) % commands_.size()] = {cmd, due, src};
    ++cmd_count_;
    if (af.command_delay > 0) ++n.commands_delayed;
    return true;
  }

  /// Hands the held commands due at tick k, in order, to deliver(cmd, src);
  /// what deliver() passes back to take() meanwhile goes through.
  template <class Deliver>
  void releaseDue(std::int64_t k, Deliver&& deliver) noexcept {
    releasing_ = true;
    while (cmd_count_ > 0 && commands_[cmd_head_].due <= k) {
      const HeldCommand held = commands_[cmd_head_];
      cmd_head_ = (cmd_head_ + 1) % commands_.size();
      --cmd_count_;
      deliver(held.cmd, held.src);
    }
    releasing_ = false;
  }

  /// The status sampled at tick k onto the channel: the one delivered this
  /// tick, or null (dropped, or still held). When several are due, the newest
  /// is delivered and the older ones are lost (a late message is superseded).
  const Status* deliverStatus(std::int64_t k, const Status& sampled, const ActiveFaults& af,
                              BusFaultCounts& n) noexcept {
    if (!enabled_) return &sampled;
    if (af.status_drop) {
      ++n.status_dropped;
    } else if (af.status_delay == 0 && st_count_ == 0) {
      return &sampled;
    } else {
      if (st_count_ == statuses_.size()) {
        st_head_ = (st_head_ + 1) % statuses_.size();
        --st_count_;
        ++n.status_dropped;
      }
      statuses_[(st_head_ + st_count_) % statuses_.size()] = {sampled, k + af.status_delay};
      ++st_count_;
      if (af.status_delay > 0) ++n.status_delayed;
    }
    std::size_t last_due = statuses_.size();  // the newest due entry
    for (std::size_t i = 0; i < st_count_; ++i) {
      if (statuses_[(st_head_ + i) % statuses_.size()].due <= k) last_due = i;
    }
    if (last_due == statuses_.size()) return nullptr;
    out_ = statuses_[(st_head_ + last_due) % statuses_.size()].status;
    n.status_dropped += static_cast<std::int64_t>(last_due);
    st_head_ = (st_head_ + last_due + 1) % statuses_.size();
    st_count_ -= last_due + 1;
    return &out_;
  }

 private:
  struct HeldStatus {
    Status status;
    std::int64_t due = 0;
  };
  struct HeldCommand {
    Command cmd;
    std::int64_t due = 0;
    SourceId src = kInProcessSource;  ///< its sender: validated against the binding when released
  };
  bool enabled_, releasing_ = false;
  std::vector<HeldStatus> statuses_;    ///< ring
  std::vector<HeldCommand> commands_;   ///< ring
  std::size_t st_head_ = 0, st_count_ = 0, cmd_head_ = 0, cmd_count_ = 0;
  Status out_;  ///< the delayed status delivered this tick
};

}  // namespace gimbalsim::firmware
