// The send side of an LCM URL, in place of liblcm's lcm_publish. Why our own:
// lcm_publish makes one system call per message, and on a virtual machine a
// lockstep bench's speed is its count of system calls (docs/bench.md
// "Lockstep speed"); here a tick's messages are staged and go out in one
// sendmmsg. The datagrams are LCM's own (LC02 short messages, the sequence
// number counting every message sent, TTL from the URL, looped back to this
// host), so liblcm programs (lcm-spy, lcm-logger, a flight controller) hear
// them as they hear lcm_publish. Only short messages: every bench message is
// under 1 kB, and a message too long for a slot is refused and counted.
// memq:// (in-process) has no socket: staged messages are dropped, as no other
// process can hear them. Allocation-free after open().
#pragma once

#include <netinet/in.h>
#include <sys/socket.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "gimbalsim/lcm_wire/udpm_reassembler.hpp"
#include "gimbalsim/lcm_wire/udpm_receiver.hpp"

namespace gimbalsim::lcm_wire {

class UdpmSender {
 public:
  static constexpr int kMaxBatch = 8;                  ///< messages staged before a flush
  static constexpr std::size_t kSlotBytes = 4096;      ///< one datagram: header, channel, payload

  UdpmSender() = default;
  ~UdpmSender();
  UdpmSender(const UdpmSender&) = delete;
  UdpmSender& operator=(const UdpmSender&) = delete;

  /// Opens the send side of `url` (parseLcmUrl's rules). False with *why on failure.
  bool open(const std::string& url, std::string* why);

  /// Stages an LCM-encoded message: `encode(buffer, capacity)` writes the
  /// payload and returns its size, or < 0 on failure (a generated type's
  /// encode). A full batch is flushed first. False (counted in errors())
  /// when the channel is not LCM's or the payload does not fit or encode.
  template <class Encode>
  bool stage(std::string_view channel, Encode&& encode) noexcept {
    if (staged_ == kMaxBatch) flush();
    const std::size_t at = kShortHeaderBytes + channel.size() + 1;
    if (channel.empty() || channel.size() > kMaxChannelBytes) return refuse();
    Slot& s = slots_[static_cast<std::size_t>(staged_)];
    const int n = encode(s.bytes.data() + at, static_cast<int>(kSlotBytes - at));
    if (n < 0 || static_cast<std::size_t>(n) > kSlotBytes - at) return refuse();
    putHeader(s, channel);
    s.size = at + static_cast<std::size_t>(n);
    ++staged_;
    return true;
  }

  /// Stages a generated LCM type (its encode into the slot: no copy).
  template <class M>
  bool stageMessage(std::string_view channel, const M& msg) noexcept {
    return stage(channel, [&msg](void* buf, int cap) { return msg.encode(buf, 0, cap); });
  }

  /// Sends every staged message in one system call (more only when the
  /// kernel takes part of the batch). Returns how many failed to go out
  /// (also added to errors()).
  int flush() noexcept;

  /// stage + flush for a lone message.
  template <class M>
  bool send(std::string_view channel, const M& msg) noexcept {
    const long long before = errors_;
    stageMessage(channel, msg);
    flush();
    return errors_ == before;
  }

  long long errors() const noexcept { return errors_; }
  long long sent() const noexcept { return sent_; }
  int staged() const noexcept { return staged_; }

 private:
  struct Slot {
    std::array<std::uint8_t, kSlotBytes> bytes;
    std::size_t size = 0;
  };
  bool refuse() noexcept {
    ++errors_;
    return false;
  }
  void putHeader(Slot& s, std::string_view channel) noexcept;

  int fd_ = -1;
  bool in_process_ = false;  ///< memq://: nobody outside hears; staged messages are dropped
  sockaddr_in to_{};
  std::uint32_t seqno_ = 0;
  std::array<Slot, kMaxBatch> slots_{};
  int staged_ = 0;
  long long errors_ = 0, sent_ = 0;
};

}  // namespace gimbalsim::lcm_wire
