// LCM's UDP multicast wire format (LCM 1.3.1, lcm/udpm_util.h; the format
// every LCM version speaks), received by our own code instead of LCM's
// receive thread: a datagram is either a whole message ("LC02": magic, the
// sender's message counter, the NUL-terminated channel name, the payload) or
// one fragment of a large message ("LC03": magic, counter, message size,
// fragment offset, fragment number, fragment count; fragment 0 carries the
// channel name before its payload). All integers are big endian.
//
// Why our own: LCM 1.3.1's receive thread segfaults on one malformed fragment
// (a datagram shorter than the fragment header underflows the payload size),
// reassembles fragments without a bound (any sender can make it allocate up
// to 16 MB per buffer, 1000 buffers) and queues only 30 messages per
// subscription, dropping the rest uncounted. This reassembler is strictly
// bounded and allocation-free after construction: a fixed number of
// reassembly buffers of a fixed size, a fixed fragment count per message, a
// timeout for partial messages, and a counter for every dropped datagram by
// reason. Only channels the process subscribes to are reassembled. Sending
// stays with liblcm (lcm_publish), so stock LCM tools still interoperate.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace gimbalsim::lcm_wire {

inline constexpr std::uint32_t kMagicShort = 0x4c433032;     ///< "LC02": a whole message in one datagram
inline constexpr std::uint32_t kMagicFragment = 0x4c433033;  ///< "LC03": one fragment of a message
inline constexpr std::size_t kShortHeaderBytes = 8;          ///< magic, msg_seqno
inline constexpr std::size_t kFragmentHeaderBytes = 20;      ///< magic, seqno, size, offset, fragment_no, count
inline constexpr std::size_t kMaxChannelBytes = 63;          ///< LCM_MAX_CHANNEL_NAME_LENGTH
inline constexpr std::size_t kMaxDatagramBytes = 65535;      ///< the largest UDP payload (IPv4: 65507)

/// Who sent a datagram: IPv4 address and UDP port in network byte order (as
/// in sockaddr_in). The kernel fills it, so a process cannot pose as another
/// process's socket without raw-socket privileges.
struct Source {
  std::uint32_t addr = 0;
  std::uint16_t port = 0;
  friend bool operator==(const Source&, const Source&) = default;
  /// One number for the pair (the firmware core compares these).
  std::uint64_t id() const noexcept { return (std::uint64_t{addr} << 16) | port; }
};

/// Why a datagram (or a partial message) was dropped. Every drop is counted.
enum class Drop : std::uint8_t {
  TooShort,       ///< shorter than its header
  BadMagic,       ///< neither "LC02" nor "LC03"
  BadChannel,     ///< channel name empty, longer than 63 bytes or not NUL-terminated inside the datagram
  NotSubscribed,  ///< a channel this process does not listen to (not an error: counted, not reassembled)
  TooLarge,       ///< message size beyond max_message_bytes, or more fragments than max_fragments
  BadFragment,    ///< fragment number >= count, count 0, size 0, data beyond the message size, fragment 0 not at offset 0
  Orphan,         ///< a fragment of a message whose fragment 0 was not seen (or was already dropped)
  Duplicate,      ///< a fragment already received
  Inconsistent,   ///< fragment count differs within one message, or the fragments do not tile the message
  Superseded,     ///< a partial message abandoned: its sender started another one
  Evicted,        ///< a partial message abandoned: every reassembly buffer was busy and it was the oldest
  TimedOut,       ///< a partial message abandoned: not complete within partial_timeout_ns
  Truncated,      ///< a datagram larger than the receive buffer (the socket layer counts it; defensive:
                  ///< the buffer holds 65535 bytes, more than any IPv4 UDP payload)
};
inline constexpr int kNumDrops = 13;
const char* describe(Drop d) noexcept;

/// The bounds; all memory is allocated once from them.
struct ReassemblyLimits {
  std::size_t max_message_bytes = 4096;      ///< payload of one message (short or reassembled) [bytes]
  int max_partials = 4;                      ///< messages being reassembled at once (buffers of max_message_bytes)
  int max_fragments = 64;                    ///< fragments of one message
  std::int64_t partial_timeout_ns = 100000000;  ///< a partial message older than this is dropped [ns]
};

/// Which channels to reassemble and deliver: a fixed list of exact names
/// (firmware_sim, pointing_controller), or a predicate (the recorder's
/// regex). The predicate is a plain function pointer: no allocation.
class ChannelFilter {
 public:
  using Predicate = bool (*)(void* ctx, std::string_view channel);
  ChannelFilter() = default;
  explicit ChannelFilter(std::vector<std::string> names) : names_(std::move(names)) {}
  ChannelFilter(Predicate p, void* ctx) : pred_(p), ctx_(ctx) {}
  /// The channel names, when the filter is a list (empty for a predicate).
  const std::vector<std::string>& names() const noexcept { return names_; }
  bool wants(std::string_view channel) const noexcept {
    if (pred_ != nullptr) return pred_(ctx_, channel);
    for (const std::string& n : names_) {
      if (channel == n) return true;
    }
    return false;
  }

 private:
  std::vector<std::string> names_;
  Predicate pred_ = nullptr;
  void* ctx_ = nullptr;
};

/// A complete message. Its bytes stay valid until the next feed().
struct Message {
  std::string_view channel;
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
  Source source;
  bool fragmented = false;  ///< reassembled from LC03 fragments
};

struct ReassemblyCounters {
  std::uint64_t datagrams = 0;             ///< fed
  std::uint64_t messages = 0;              ///< delivered (short and reassembled)
  std::uint64_t reassembled = 0;           ///< of which from fragments
  std::array<std::uint64_t, kNumDrops> drops{};  ///< per Drop
  std::uint64_t dropped() const noexcept {
    std::uint64_t n = 0;
    for (std::uint64_t d : drops) n += d;
    return n;
  }
};

class Reassembler {
 public:
  Reassembler(const ReassemblyLimits& limits, ChannelFilter filter);

  /// One datagram from `src`, received at now_ns (any monotonic clock). Returns
  /// the message it completes, or null (dropped, counted; or a fragment
  /// stored). Allocation-free, noexcept, O(datagram size + max_partials).
  const Message* feed(const std::uint8_t* d, std::size_t n, Source src, std::int64_t now_ns) noexcept;

  /// Drops partial messages older than the timeout (feed() does it too).
  void expire(std::int64_t now_ns) noexcept;

  /// Counts a drop decided outside (the socket layer's Truncated).
  void count(Drop d) noexcept { ++n_.drops[static_cast<int>(d)]; }

  const ReassemblyCounters& counters() const noexcept { return n_; }
  const ReassemblyLimits& limits() const noexcept { return lim_; }
  int partialsInFlight() const noexcept;

 private:
  struct Partial {
    bool used = false;
    Source src;
    std::uint32_t seqno = 0, size = 0;
    std::uint16_t count = 0, got = 0;
    std::int64_t started_ns = 0;
    std::uint8_t channel_len = 0;
    char channel[kMaxChannelBytes + 1] = {};
    std::uint8_t* data = nullptr;   ///< max_message_bytes in the arena
    std::uint64_t* seen = nullptr;  ///< one bit per fragment
    std::uint32_t* range = nullptr; ///< offset and length of each fragment, by fragment number
  };

  const Message* dropped(Drop d) noexcept {
    count(d);
    return nullptr;
  }
  void release(Partial& p, Drop why) noexcept;
  const Message* feedShort(const std::uint8_t* d, std::size_t n, Source src) noexcept;
  const Message* feedFragment(const std::uint8_t* d, std::size_t n, Source src, std::int64_t now_ns) noexcept;

  ReassemblyLimits lim_;
  ChannelFilter filter_;
  std::size_t seen_words_ = 1;
  std::vector<std::uint8_t> arena_;
  std::vector<std::uint64_t> seen_arena_;
  std::vector<std::uint32_t> range_arena_;
  std::vector<Partial> partials_;
  Message out_;
  ReassemblyCounters n_;
};

}  // namespace gimbalsim::lcm_wire
