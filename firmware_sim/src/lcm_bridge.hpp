// firmware_sim's LCM side: receives with our bounded UDP receiver
// (bench_io/udpm_receiver.hpp, not LCM's receive thread: see there why),
// decodes gimbal_command_t into the inbound ring with its sender,
// publishes status, attitude, truth and loop statistics from a preallocated buffer with
// the raw publish (the typed one allocates on every call), and times the
// status -> command round trip. Runs on the communication thread (real time)
// or the only thread (lockstep); the loop thread never calls it.
#pragma once

#include <cstdint>
#include <string>

#include "app.hpp"
#include "gimbalsim/bench_io/udpm_receiver.hpp"
#include "gimbalsim/contract/channels.hpp"
#include "gimbalsim/firmware_sim/histogram.hpp"

namespace gimbalsim::firmware {

class LcmBridge {
 public:
  /// Receives the command channel through `rx` (opened on the same URL as
  /// `lcm`, filtering that channel); decoded commands go to `in`.
  LcmBridge(lcm::LCM& lcm, bench_io::UdpmReceiver& rx, Channels ch, SpscRing<Inbound>& in);

  /// The receiver's limits for firmware_sim: bench messages are < 1 kB.
  static bench_io::ReassemblyLimits receiveLimits();

  /// Reads the datagrams waiting (at most kDrainMax) into the inbound ring.
  void drain();
  /// Waits up to timeout_ms for datagrams (busy-polling the first spin_ns),
  /// then drain(). False on a socket error.
  bool receive(int timeout_ms, std::int64_t spin_ns = 0);
  int fd() const noexcept { return rx_.fd(); }
  const bench_io::UdpmReceiver& receiver() const noexcept { return rx_; }

  void publish(const Status& s);
  void publish(const Truth& t);
  void publish(const Attitude& a);
  void publishStats(std::int64_t utime, const LoopStats& st, bool realtime, bool lockstep);

  /// Status published -> command answering it received [us] (this thread only).
  Histogram roundtrip{10000};
  long long dropped_in = 0;  ///< commands lost because the inbound ring was full (counted, never silent)
  long long publish_errors = 0;

 private:
  void onCommand(const bench_io::Message& msg);
  static constexpr int kDrainMax = 256;  ///< datagrams per drain(): a flood cannot starve publishing
  template <class M>
  void send(const std::string& channel, const M& msg);

  lcm::LCM& lcm_;
  bench_io::UdpmReceiver& rx_;
  Channels ch_;
  SpscRing<Inbound>& in_;
  Status last_status_;
  unsigned char buf_[2048];
  static constexpr std::size_t kRoundTripSlots = 1024;
  std::int64_t pub_seq_[kRoundTripSlots];  ///< seq of the status published in each slot (-1: answered)
  std::int64_t pub_ns_[kRoundTripSlots];   ///< when it was published [ns, CLOCK_MONOTONIC]
};

}  // namespace gimbalsim::firmware
