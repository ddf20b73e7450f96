// firmware_sim's LCM side: receives with our bounded UDP receiver
// (lcm_wire/udpm_receiver.hpp, not LCM's receive thread: see there why),
// decodes gimbal_command_t and hands it, with its sender, to the loop's
// command sink (app.hpp),
// stages status, attitude, truth and loop statistics in our sender
// (lcm_wire/udpm_sender.hpp: a tick's messages go out in one system call at
// flush()), and times the status -> command round trip. Runs on the communication thread (real time)
// or the only thread (lockstep); the loop thread never calls it.
#pragma once

#include <cstdint>
#include <string>

#include "app.hpp"
#include "gimbalsim/lcm_wire/udpm_receiver.hpp"
#include "gimbalsim/lcm_wire/udpm_sender.hpp"
#include "gimbalsim/contract/channels.hpp"
#include "gimbalsim/firmware_sim/histogram.hpp"

namespace gimbalsim::firmware {

class LcmBridge {
 public:
  /// Receives the command channel through `rx` and sends through `tx` (both
  /// opened on the one URL; rx filtering that channel); decoded commands go to the sink set.
  LcmBridge(lcm_wire::UdpmSender& tx, lcm_wire::UdpmReceiver& rx, Channels ch);

  /// Where decoded commands go (null: none, each counted in dropped_in).
  void setSink(CommandSink* sink) noexcept { sink_ = sink; }

  /// The receiver's limits for firmware_sim: bench messages are < 1 kB.
  static lcm_wire::ReassemblyLimits receiveLimits();

  /// Reads the datagrams waiting (at most kDrainMax) into the inbound ring.
  void drain();
  /// Waits up to timeout_ms for datagrams (busy-polling the first spin_ns)
  /// and reads them, in one system call when one comes (UdpmReceiver::waitDrain).
  /// False on a socket error.
  bool receive(int timeout_ms, std::int64_t spin_ns = 0);
  int fd() const noexcept { return rx_.fd(); }
  const lcm_wire::UdpmReceiver& receiver() const noexcept { return rx_; }

  /// Each publish stages its message; flush() sends what is staged, in the
  /// order staged (a full batch goes out by itself). A failure is counted in publishErrors().
  void publish(const Status& s);
  void publish(const Truth& t);
  void publish(const Attitude& a);
  void publish(const Antenna& a);
  void publishStats(std::int64_t utime, const LoopStats& st, bool realtime, bool lockstep);
  void flush() noexcept;

  /// Status published -> command answering it received [us] (this thread only).
  Histogram roundtrip{10000};
  long long dropped_in = 0;  ///< commands the sink could not take (counted, never silent)
  long long publishErrors() const noexcept { return tx_.errors(); }

 private:
  void onCommand(const lcm_wire::Message& msg);
  static constexpr int kDrainMax = 256;  ///< datagrams per drain(): a flood cannot starve publishing
  lcm_wire::UdpmSender& tx_;
  lcm_wire::UdpmReceiver& rx_;
  Channels ch_;
  CommandSink* sink_ = nullptr;
  Status last_status_;
  static constexpr std::size_t kRoundTripSlots = 1024;
  std::int64_t pub_seq_[kRoundTripSlots];  ///< seq of the status published in each slot (-1: answered)
  std::int64_t pub_ns_[kRoundTripSlots];   ///< when it was sent (its flush) [ns, CLOCK_MONOTONIC]
  int unsent_slot_ = -1;                   ///< the slot of a status staged and not yet flushed (-1: none)
};

/// A sink bound to the bridge for one scope (a loop's run).
class SinkBinding {
 public:
  SinkBinding(LcmBridge& bridge, CommandSink* sink) noexcept : bridge_(bridge) { bridge_.setSink(sink); }
  ~SinkBinding() { bridge_.setSink(nullptr); }
  SinkBinding(const SinkBinding&) = delete;
  SinkBinding& operator=(const SinkBinding&) = delete;

 private:
  LcmBridge& bridge_;
};

}  // namespace gimbalsim::firmware
