// The receive side of an LCM URL, in place of LCM's receive thread (why:
// udpm_reassembler.hpp). udpm://GROUP:PORT?opts: a UDP socket bound to the
// multicast group and port (SO_REUSEADDR, so lcm-logger, lcm-spy and other LCM
// programs on the host listen too), datagrams read without blocking on the
// caller's thread and fed to a bounded Reassembler. memq:// is LCM's
// in-process provider: another process never hears anything on it, so the
// receiver has no socket and delivers nothing. Other providers are refused.
// Sending stays with liblcm's lcm_publish on the same URL.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "gimbalsim/lcm_wire/udpm_reassembler.hpp"

namespace gimbalsim::lcm_wire {

/// An LCM URL as the receiver needs it. An empty URL means LCM_DEFAULT_URL,
/// else LCM's default udpm://239.255.76.67:7667?ttl=0 (as lcm_create does).
struct LcmUrl {
  enum class Kind { Udpm, InProcess, Unsupported } kind = Kind::Unsupported;
  std::string text;          ///< the URL in effect
  std::uint32_t group = 0;   ///< multicast group, network byte order
  std::uint16_t port = 0;    ///< [-] host byte order
  int recv_buf_size = 0;     ///< [bytes] the URL's recv_buf_size option (0: not given)
};

/// Parses `url`; on failure kind is Unsupported and *why says what is wrong.
LcmUrl parseLcmUrl(const std::string& url, std::string* why);

/// What is wrong with a --lcm-url value ("" when nothing): the programs'
/// check of the flag, so a malformed URL is a bad argument (exit 2), never
/// "the network could not start" (5).
inline std::string lcmUrlProblem(const std::string& url) {
  std::string why;
  return parseLcmUrl(url, &why).kind == LcmUrl::Kind::Unsupported ? why : std::string();
}

/// What is wrong with the URL a program takes when --lcm-url is not given
/// (`given` empty): LCM_DEFAULT_URL, checked as the flag is, so a bad one is a
/// bad argument (2) too, not "LCM could not start" (5). "" when nothing.
inline std::string defaultLcmUrlProblem(const std::string& given) {
  if (!given.empty()) return {};  // the flag's own check (lcmUrlProblem) has read it
  const std::string why = lcmUrlProblem("");
  return why.empty() ? why : "LCM_DEFAULT_URL (the URL without --lcm-url): " + why;
}

class UdpmReceiver {
 public:
  UdpmReceiver(const ReassemblyLimits& limits, ChannelFilter filter);
  ~UdpmReceiver();
  UdpmReceiver(const UdpmReceiver&) = delete;
  UdpmReceiver& operator=(const UdpmReceiver&) = delete;

  /// Opens the receive side of `url`; recv_buf_bytes is the socket buffer to
  /// ask for when the URL does not set one. False with *why on failure.
  /// With a filter of channel names, a socket filter in the kernel drops the
  /// whole (LC02) messages on other channels before they are queued, so the
  /// bench's other traffic (a plant's own statuses and truths) wakes nobody;
  /// fragments and non-LCM datagrams still come up to be checked and counted.
  bool open(const std::string& url, int recv_buf_bytes, std::string* why);

  /// The socket to poll for POLLIN; -1 when there is none (memq://).
  int fd() const noexcept { return fd_; }

  /// Waits up to timeout_ms for a datagram: 1 one is waiting, 0 timeout or a
  /// signal (EINTR), -1 a socket error. Without a socket it just sleeps.
  /// spin_ns > 0 polls without sleeping for that long first, yielding the CPU
  /// between polls: a lockstep peer that answers within it is seen without
  /// waking a halted CPU, which costs tens of us on a virtual machine, and a
  /// peer on the same CPU runs at once (docs/bench.md "Lockstep speed").
  int wait(int timeout_ms, std::int64_t spin_ns = 0) noexcept;

  /// Reads one waiting datagram without blocking. Returns the message it
  /// completes or null; *empty is true when nothing was waiting (or on an error).
  /// recv_utime: wall-clock receive time [us]. Allocation-free.
  const Message* readOne(bool* empty, std::int64_t* recv_utime = nullptr) noexcept;

  /// Reads at most max_datagrams waiting datagrams and calls on(const Message&,
  /// std::int64_t recv_utime) for each complete message. Returns the number of
  /// datagrams read. The bound keeps a flood from starving the caller's other work.
  template <class F>
  int drain(F&& on, int max_datagrams) {
    int read = 0;
    for (; read < max_datagrams; ++read) {
      bool empty = false;
      std::int64_t t = 0;
      const Message* m = readOne(&empty, &t);
      if (empty) break;
      if (m != nullptr) on(*m, t);
    }
    return read;
  }

  const ReassemblyCounters& counters() const noexcept { return rs_.counters(); }
  const Reassembler& reassembler() const noexcept { return rs_; }
  std::uint64_t socketErrors() const noexcept { return socket_errors_; }
  /// Datagrams the kernel dropped because the socket buffer was full (SO_RXQ_OVFL, as of the last datagram read);
  /// with the kernel filter, its drops too (the kernel counts them together).
  std::uint64_t kernelDrops() const noexcept { return kernel_drops_; }
  /// The socket's receive buffer as granted by the kernel [bytes] (0: no socket).
  int recvBufferBytes() const noexcept { return rcvbuf_; }
  /// The kernel drops other channels' whole messages (open() attached the filter).
  bool kernelFilter() const noexcept { return kernel_filter_; }
  /// One line for an exit summary: datagrams, messages, drops by reason.
  std::string summary() const;

 private:
  Reassembler rs_;
  std::vector<std::string> kernel_channels_;  ///< names the kernel filter lets through (empty: no filter)
  bool kernel_filter_ = false;                ///< the socket filter is attached
  int fd_ = -1;
  int rcvbuf_ = 0;
  std::uint64_t socket_errors_ = 0;
  std::uint64_t kernel_drops_ = 0;
  std::vector<std::uint8_t> buf_;
};

/// CLOCK_MONOTONIC [ns] (the reassembler's timeout clock).
std::int64_t monotonicNs() noexcept;


}  // namespace gimbalsim::lcm_wire
