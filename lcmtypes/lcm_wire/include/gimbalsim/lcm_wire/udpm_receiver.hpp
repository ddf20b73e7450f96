// The receive side of an LCM URL, in place of LCM's receive thread (why:
// udpm_reassembler.hpp). udpm://GROUP:PORT?opts: a UDP socket bound to the
// multicast group and port (SO_REUSEADDR, so lcm-logger, lcm-spy and other LCM
// programs on the host listen too), datagrams read without blocking on the
// caller's thread and fed to a bounded Reassembler. memq:// is LCM's
// in-process provider: another process never hears anything on it, so the
// receiver has no socket and delivers nothing. Other providers are refused.
// Sending: udpm_sender.hpp, on the same URL.
#pragma once

#include <algorithm>
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
  int ttl = 0;               ///< [hops] multicast TTL of what is sent (LCM's default 0: this host only)
};

/// Parses `url`; on failure kind is Unsupported and *why says what is wrong.
LcmUrl parseLcmUrl(const std::string& url, std::string* why);

/// The sender's and the receiver's open(), on a socket step that failed: closes
/// *fd (sets -1), says in *why the URL, the step and errno's text (with how to
/// add a multicast route when the host has none), and returns false.
bool socketStepFailed(const LcmUrl& u, const char* step, int* fd, std::string* why);

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

  /// Reads at most max_datagrams waiting datagrams and calls on(const Message&,
  /// std::int64_t recv_utime) for each complete message (recv_utime: wall-clock
  /// receive time [us]). Returns the number of datagrams read. The bound keeps a
  /// flood from starving the caller's other work. One system call (recvmmsg) per
  /// kBatch datagrams, and none more to find the queue empty: a lockstep tick's
  /// intake is one call. Allocation-free.
  template <class F>
  int drain(F&& on, int max_datagrams) {
    int read = 0;
    while (read < max_datagrams) {
      const int want = std::min(kBatch, max_datagrams - read);
      const int n = std::max(0, readBatch(want));
      deliver(n, on);
      read += n;
      if (n < want) break;  // fewer than asked: nothing more was waiting (or an error)
    }
    return read;
  }

  /// wait() and drain() in one: blocks up to timeout_ms (after a spin of
  /// spin_ns, as wait()) for the first datagram and reads it with those
  /// already waiting in the same system call, so a lockstep turn's wait and
  /// read cost one call, not two. Returns the datagrams read (0: timeout or a
  /// signal), -1 on a socket error. Allocation-free.
  template <class F>
  int waitDrain(int timeout_ms, std::int64_t spin_ns, F&& on, int max_datagrams) {
    if (fd_ < 0 || spin_ns > 0) {  // no socket (sleeps), or a spin first: wait() then a drain
      const int w = wait(fd_ < 0 ? timeout_ms : 0, spin_ns);
      if (w < 0) return -1;
      if (w > 0 || fd_ < 0) return w > 0 ? drain(on, max_datagrams) : 0;
    }
    const int want = std::min(kBatch, max_datagrams);
    const int n = readBatch(want, timeout_ms);
    if (n <= 0) return n;
    deliver(n, on);
    return n == want && n < max_datagrams ? n + drain(on, max_datagrams - n) : n;
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
  static constexpr int kBatch = 8;  ///< datagrams per recvmmsg
  /// Reads up to `want` (<= kBatch) waiting datagrams; their count. With
  /// block_ms > 0 it first blocks up to that long for one (0 on timeout or a
  /// signal); -1 on a socket error then (never without blocking: 0).
  int readBatch(int want, int block_ms = 0) noexcept;
  int rcvtimeo_ms_ = -1;  ///< the socket's SO_RCVTIMEO as last set [ms] (-1: never)
  /// Feeds datagram i of the last batch to the reassembler: the message it completes or null.
  const Message* feedRead(int i, std::int64_t* recv_utime) noexcept;
  /// Hands on(message, receive time [us]) each message the last batch's first n datagrams complete.
  template <class F>
  void deliver(int n, F& on) {
    for (int i = 0; i < n; ++i) {
      std::int64_t t = 0;
      if (const Message* m = feedRead(i, &t)) on(*m, t);
    }
  }
  std::vector<std::uint8_t> buf_;      ///< kBatch datagram buffers of kMaxDatagramBytes + 1 (a longer one is seen)
  std::vector<std::size_t> len_;       ///< each datagram's real length (MSG_TRUNC)
  std::vector<Source> from_;           ///< each datagram's sender
  std::int64_t batch_utime_ = 0;       ///< when the last batch was read [us, CLOCK_REALTIME]
};

/// CLOCK_MONOTONIC [ns] (the reassembler's timeout clock).
std::int64_t monotonicNs() noexcept;


}  // namespace gimbalsim::lcm_wire
