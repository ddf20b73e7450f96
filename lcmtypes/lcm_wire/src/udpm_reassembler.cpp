#include "gimbalsim/lcm_wire/udpm_reassembler.hpp"

#include <algorithm>
#include <cstring>

namespace gimbalsim::lcm_wire {
namespace {

std::uint32_t be32(const std::uint8_t* p) noexcept {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}
std::uint16_t be16(const std::uint8_t* p) noexcept { return static_cast<std::uint16_t>((p[0] << 8) | p[1]); }

/// Length of the NUL-terminated channel name at p (at most `avail` bytes
/// readable), or -1 when it is empty, too long or not terminated in range.
int channelLength(const std::uint8_t* p, std::size_t avail) noexcept {
  const std::size_t lim = std::min(avail, kMaxChannelBytes + 1);
  const void* nul = std::memchr(p, 0, lim);
  if (nul == nullptr) return -1;
  const auto len = static_cast<const std::uint8_t*>(nul) - p;
  return len == 0 ? -1 : static_cast<int>(len);
}

}  // namespace

const char* describe(Drop d) noexcept {
  switch (d) {
    case Drop::TooShort: return "shorter than its header";
    case Drop::BadMagic: return "bad magic (not LC02/LC03)";
    case Drop::BadChannel: return "bad channel name";
    case Drop::NotSubscribed: return "channel not subscribed";
    case Drop::TooLarge: return "message or fragment count beyond the limit";
    case Drop::BadFragment: return "malformed fragment header";
    case Drop::Orphan: return "fragment without its fragment 0";
    case Drop::Duplicate: return "duplicate fragment";
    case Drop::Inconsistent: return "fragments inconsistent with their message";
    case Drop::Superseded: return "partial message superseded by its sender's next";
    case Drop::Evicted: return "partial message evicted (all reassembly buffers busy)";
    case Drop::TimedOut: return "partial message timed out";
    case Drop::Truncated: return "datagram larger than the receive buffer";
  }
  return "?";
}

Reassembler::Reassembler(const ReassemblyLimits& limits, ChannelFilter filter)
    : lim_(limits), filter_(std::move(filter)) {
  lim_.max_partials = std::max(1, lim_.max_partials);
  lim_.max_fragments = std::clamp(lim_.max_fragments, 1, 65535);
  seen_words_ = (static_cast<std::size_t>(lim_.max_fragments) + 63) / 64;
  const auto np = static_cast<std::size_t>(lim_.max_partials);
  arena_.assign(np * lim_.max_message_bytes, 0);
  seen_arena_.assign(np * seen_words_, 0);
  const auto nf = static_cast<std::size_t>(lim_.max_fragments);
  range_arena_.assign(np * 2 * nf, 0);
  partials_.resize(np);
  for (std::size_t i = 0; i < np; ++i) {
    partials_[i].data = arena_.data() + i * lim_.max_message_bytes;
    partials_[i].seen = seen_arena_.data() + i * seen_words_;
    partials_[i].range = range_arena_.data() + i * 2 * nf;
  }
}

int Reassembler::partialsInFlight() const noexcept {
  return static_cast<int>(std::count_if(partials_.begin(), partials_.end(), [](const Partial& p) { return p.used; }));
}

void Reassembler::release(Partial& p, Drop why) noexcept {
  count(why);
  p.used = false;
}

void Reassembler::expire(std::int64_t now_ns) noexcept {
  for (Partial& p : partials_) {
    // Measured from the first fragment, so a slow drip cannot keep a buffer forever.
    if (p.used && now_ns - p.started_ns > lim_.partial_timeout_ns) release(p, Drop::TimedOut);
  }
}

const Message* Reassembler::feed(const std::uint8_t* d, std::size_t n, Source src, std::int64_t now_ns) noexcept {
  ++n_.datagrams;
  expire(now_ns);
  if (n < 4) return dropped(Drop::TooShort);
  const std::uint32_t magic = be32(d);
  if (magic == kMagicShort) return feedShort(d, n, src);
  if (magic == kMagicFragment) return feedFragment(d, n, src, now_ns);
  return dropped(Drop::BadMagic);
}

const Message* Reassembler::feedShort(const std::uint8_t* d, std::size_t n, Source src) noexcept {
  if (n < kShortHeaderBytes) return dropped(Drop::TooShort);
  const std::uint8_t* ch = d + kShortHeaderBytes;
  const int len = channelLength(ch, n - kShortHeaderBytes);
  if (len < 0) return dropped(Drop::BadChannel);
  const std::string_view channel(reinterpret_cast<const char*>(ch), static_cast<std::size_t>(len));
  if (!filter_.wants(channel)) return dropped(Drop::NotSubscribed);
  const std::size_t head = kShortHeaderBytes + static_cast<std::size_t>(len) + 1;
  if (n - head > lim_.max_message_bytes) return dropped(Drop::TooLarge);
  out_ = Message{channel, d + head, n - head, src, false};
  ++n_.messages;
  return &out_;
}

const Message* Reassembler::feedFragment(const std::uint8_t* d, std::size_t n, Source src,
                                         std::int64_t now_ns) noexcept {
  if (n < kFragmentHeaderBytes) return dropped(Drop::TooShort);  // LCM 1.3.1 underflows here
  const std::uint32_t seqno = be32(d + 4);
  const std::uint32_t size = be32(d + 8);
  const std::uint32_t offset = be32(d + 12);
  const std::uint16_t frag_no = be16(d + 16);
  const std::uint16_t count = be16(d + 18);
  if (size > lim_.max_message_bytes || count > lim_.max_fragments) return dropped(Drop::TooLarge);
  if (size == 0 || count == 0 || frag_no >= count) return dropped(Drop::BadFragment);

  // One message in reassembly per sender, as LCM does: a new one supersedes it.
  Partial* p = nullptr;
  for (Partial& q : partials_) {
    if (q.used && q.src == src) p = &q;
  }
  if (p != nullptr && (p->seqno != seqno || p->size != size)) {
    release(*p, Drop::Superseded);
    p = nullptr;
  }

  const std::uint8_t* payload = d + kFragmentHeaderBytes;
  std::size_t len = n - kFragmentHeaderBytes;
  if (frag_no == 0) {
    const int clen = channelLength(payload, len);
    if (clen < 0) return dropped(Drop::BadChannel);
    const std::string_view channel(reinterpret_cast<const char*>(payload), static_cast<std::size_t>(clen));
    if (!filter_.wants(channel)) return dropped(Drop::NotSubscribed);
    if (offset != 0) return dropped(Drop::BadFragment);
    payload += clen + 1;
    len -= static_cast<std::size_t>(clen) + 1;
    if (p == nullptr) {
      // A free buffer, else the oldest partial message makes room.
      for (Partial& q : partials_) {
        if (!q.used) {
          p = &q;
          break;
        }
      }
      if (p == nullptr) {
        p = &*std::min_element(partials_.begin(), partials_.end(),
                               [](const Partial& a, const Partial& b) { return a.started_ns < b.started_ns; });
        release(*p, Drop::Evicted);
      }
      p->used = true;
      p->src = src;
      p->seqno = seqno;
      p->size = size;
      p->count = count;
      p->got = 0;
      p->started_ns = now_ns;
      p->channel_len = static_cast<std::uint8_t>(clen);
      std::memcpy(p->channel, channel.data(), channel.size());
      p->channel[clen] = '\0';
      std::fill(p->seen, p->seen + seen_words_, 0);
    }
  } else if (p == nullptr) {
    return dropped(Drop::Orphan);
  }

  if (count != p->count) return dropped(Drop::Inconsistent);
  std::uint64_t& word = p->seen[frag_no / 64];
  const std::uint64_t bit = std::uint64_t{1} << (frag_no % 64);
  if (word & bit) return dropped(Drop::Duplicate);
  if (std::uint64_t{offset} + len > p->size) return dropped(Drop::BadFragment);
  std::memcpy(p->data + offset, payload, len);
  word |= bit;
  p->range[2 * frag_no] = offset;
  p->range[2 * frag_no + 1] = static_cast<std::uint32_t>(len);
  ++p->got;
  if (p->got < p->count) return nullptr;
  // LCM cuts a message into consecutive pieces in fragment order: they must
  // tile [0, size) exactly (no overlap, no hole of stale bytes).
  std::uint64_t end = 0;
  for (std::uint16_t i = 0; i < p->count; ++i) {
    if (p->range[2 * i] != end) break;
    end += p->range[2 * i + 1];
  }
  if (end != p->size) {
    release(*p, Drop::Inconsistent);
    return nullptr;
  }
  out_ = Message{std::string_view(p->channel, p->channel_len), p->data, p->size, src, true};
  p->used = false;  // the bytes stay in place until the buffer is reused by a later feed()
  ++n_.messages;
  ++n_.reassembled;
  return &out_;
}

}  // namespace gimbalsim::lcm_wire
