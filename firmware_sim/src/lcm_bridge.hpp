// firmware_sim's LCM side: decodes gimbal_command_t into the inbound ring,
// publishes status, attitude, truth and loop statistics from a preallocated buffer with
// the raw publish (the typed one allocates on every call), and times the
// status -> command round trip. Runs on the communication thread (real time)
// or the only thread (lockstep); the loop thread never calls it.
#pragma once

#include <cstdint>
#include <string>

#include "app.hpp"
#include "gimbalsim/channels.hpp"
#include "gimbalsim/firmware/histogram.hpp"

namespace lcm {
class ReceiveBuffer;
}

namespace gimbalsim::firmware {

class LcmBridge {
 public:
  /// Subscribes to the command channel; decoded commands go to `in`.
  LcmBridge(lcm::LCM& lcm, Channels ch, SpscRing<Inbound>& in);

  void publish(const Status& s);
  void publish(const Truth& t);
  void publish(const Attitude& a);
  void publishStats(std::int64_t utime, const LoopStats& st, bool realtime, bool lockstep);

  /// Status published -> command answering it received [us] (this thread only).
  Histogram roundtrip{10000};
  long long dropped_in = 0;  ///< commands lost because the inbound ring was full
  long long publish_errors = 0;

 private:
  void onCommand(const lcm::ReceiveBuffer* rb, const std::string& channel);
  template <class M>
  void send(const std::string& channel, const M& msg);

  lcm::LCM& lcm_;
  Channels ch_;
  SpscRing<Inbound>& in_;
  Status last_status_;
  unsigned char buf_[2048];
  static constexpr std::size_t kRoundTripSlots = 1024;
  std::int64_t pub_seq_[kRoundTripSlots];  ///< seq of the status published in each slot (-1: answered)
  std::int64_t pub_ns_[kRoundTripSlots];   ///< when it was published [ns, CLOCK_MONOTONIC]
};

}  // namespace gimbalsim::firmware
