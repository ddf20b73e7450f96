// The bounded receive path (lcm_wire/udpm_reassembler.hpp): short messages and
// reassembly as LCM sends them, every bound, every drop reason, the partial
// timeout, and no allocation per datagram. Datagrams are built byte by byte
// from the wire format (lcm_datagrams.hpp), independently of the parser;
// tests/hil/udpm_interop_test.cpp checks against liblcm's own sender.
#include "gimbalsim/lcm_wire/udpm_reassembler.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "alloc_guard.hpp"
#include "lcm_wire/lcm_datagrams.hpp"

namespace gimbalsim::lcm_wire {
namespace {

using datagrams::Bytes;
using datagrams::fragment;

Bytes shortMsg(const std::string& ch, const Bytes& payload) { return datagrams::shortMessage(ch, payload); }

Bytes pattern(std::size_t n, std::uint8_t salt = 0) {
  Bytes b(n);
  for (std::size_t i = 0; i < n; ++i) b[i] = static_cast<std::uint8_t>(i * 31 + salt);
  return b;
}

/// `msg` cut as LCM cuts it: fragment 0 carries the channel and frag-(len+1) bytes.
std::vector<Bytes> fragmentsOf(const std::string& ch, const Bytes& msg, std::size_t frag, std::uint32_t seq = 7) {
  std::vector<Bytes> out;
  const std::size_t first = frag - (ch.size() + 1);
  const std::size_t count = 1 + (msg.size() - first + frag - 1) / frag;
  std::size_t off = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t len = std::min(i == 0 ? first : frag, msg.size() - off);
    out.push_back(fragment(seq, static_cast<std::uint32_t>(msg.size()), static_cast<std::uint32_t>(off),
                           static_cast<std::uint16_t>(i), static_cast<std::uint16_t>(count), ch,
                           Bytes(msg.begin() + off, msg.begin() + off + len)));
    off += len;
  }
  return out;
}

const Source kA{0x0100007f, 1000}, kB{0x0100007f, 2000};

struct Rx {
  ReassemblyLimits lim;
  Reassembler r;
  explicit Rx(ReassemblyLimits l = {}) : lim(l), r(l, ChannelFilter({"CMD", "STATUS"})) {}
  const Message* feed(const Bytes& b, Source s = kA, std::int64_t t = 0) { return r.feed(b.data(), b.size(), s, t); }
  std::uint64_t drops(Drop d) const { return r.counters().drops[static_cast<int>(d)]; }
};

TEST(UdpmReassembler, ShortMessageIsDeliveredWithChannelPayloadAndSource) {
  Rx rx;
  const Bytes p = pattern(49);
  const Bytes d = shortMsg("CMD", p);  // the message points into the datagram
  const Message* m = rx.feed(d, kB);
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->channel, "CMD");
  EXPECT_EQ(Bytes(m->data, m->data + m->size), p);
  EXPECT_EQ(m->source, kB);
  EXPECT_FALSE(m->fragmented);
  EXPECT_EQ(rx.r.counters().messages, 1u);
  EXPECT_EQ(rx.r.counters().dropped(), 0u);
  // An empty payload is a message too.
  EXPECT_NE(rx.feed(shortMsg("STATUS", {})), nullptr);
}

TEST(UdpmReassembler, MalformedShortDatagramsAreDroppedByReason) {
  Rx rx;
  EXPECT_EQ(rx.feed(Bytes{0x4c, 0x43, 0x30}), nullptr);  // 3 bytes
  EXPECT_EQ(rx.feed(Bytes{0x4c, 0x43, 0x30, 0x32, 0, 0, 0}), nullptr);  // LC02, 7 bytes
  EXPECT_EQ(rx.drops(Drop::TooShort), 2u);
  Bytes bad = shortMsg("CMD", pattern(8));
  bad[0] = 'X';
  EXPECT_EQ(rx.feed(bad), nullptr);
  EXPECT_EQ(rx.drops(Drop::BadMagic), 1u);
  EXPECT_EQ(rx.feed(shortMsg("", pattern(8))), nullptr);                   // empty channel
  const Bytes unterminated = datagrams::shortMessage("CMD", {}, 1, false);  // the datagram ends inside the name
  EXPECT_EQ(rx.feed(unterminated), nullptr);
  EXPECT_EQ(rx.feed(shortMsg(std::string(64, 'C'), pattern(8))), nullptr);  // 64 > 63 bytes
  EXPECT_EQ(rx.drops(Drop::BadChannel), 3u);
  EXPECT_EQ(rx.feed(shortMsg("OTHER", pattern(8))), nullptr);
  EXPECT_EQ(rx.drops(Drop::NotSubscribed), 1u);
  EXPECT_EQ(rx.feed(shortMsg("CMD", pattern(rx.lim.max_message_bytes + 1))), nullptr);
  EXPECT_EQ(rx.drops(Drop::TooLarge), 1u);
  EXPECT_NE(rx.feed(shortMsg("CMD", pattern(rx.lim.max_message_bytes))), nullptr) << "the limit itself is allowed";
  EXPECT_EQ(rx.r.counters().datagrams, 9u);
  EXPECT_EQ(rx.r.counters().messages, 1u);
  EXPECT_EQ(rx.r.counters().dropped(), 8u);
}

TEST(UdpmReassembler, FragmentsInOrderReassembleTheMessage) {
  Rx rx;
  const Bytes msg = pattern(3000, 5);
  const std::vector<Bytes> fr = fragmentsOf("STATUS", msg, 1000);
  ASSERT_EQ(fr.size(), 4u);
  for (std::size_t i = 0; i + 1 < fr.size(); ++i) {
    EXPECT_EQ(rx.feed(fr[i]), nullptr);
    EXPECT_EQ(rx.r.partialsInFlight(), 1);
  }
  const Message* m = rx.feed(fr.back());
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->channel, "STATUS");
  EXPECT_TRUE(m->fragmented);
  EXPECT_EQ(Bytes(m->data, m->data + m->size), msg);
  EXPECT_EQ(rx.r.partialsInFlight(), 0);
  EXPECT_EQ(rx.r.counters().reassembled, 1u);
  EXPECT_EQ(rx.r.counters().dropped(), 0u);
}

TEST(UdpmReassembler, LaterFragmentsMayArriveOutOfOrderButFragmentZeroOpensTheMessage) {
  Rx rx;
  const Bytes msg = pattern(2500, 9);
  std::vector<Bytes> fr = fragmentsOf("CMD", msg, 1000);
  ASSERT_EQ(fr.size(), 3u);
  EXPECT_EQ(rx.feed(fr[2]), nullptr);  // before fragment 0: nobody knows its channel yet
  EXPECT_EQ(rx.drops(Drop::Orphan), 1u);
  EXPECT_EQ(rx.feed(fr[0]), nullptr);
  EXPECT_EQ(rx.feed(fr[2]), nullptr);
  const Message* m = rx.feed(fr[1]);
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(Bytes(m->data, m->data + m->size), msg);
}

TEST(UdpmReassembler, DuplicateAndMalformedFragmentsAreDroppedByReason) {
  Rx rx;
  const Bytes msg = pattern(2500);
  std::vector<Bytes> fr = fragmentsOf("CMD", msg, 1000);
  EXPECT_EQ(rx.feed(fr[0]), nullptr);
  EXPECT_EQ(rx.feed(fr[1]), nullptr);
  EXPECT_EQ(rx.feed(fr[1]), nullptr);
  EXPECT_EQ(rx.drops(Drop::Duplicate), 1u);
  EXPECT_EQ(rx.feed(Bytes(fr[2].begin(), fr[2].begin() + 19)), nullptr);  // cut inside the 20-byte header
  EXPECT_EQ(rx.drops(Drop::TooShort), 1u);
  EXPECT_EQ(rx.feed(fragment(7, 2500, 2000, 3, 3, "", pattern(10))), nullptr);  // fragment_no >= count
  EXPECT_EQ(rx.feed(fragment(7, 2500, 2000, 2, 0, "", pattern(10))), nullptr);  // count 0
  EXPECT_EQ(rx.feed(fragment(7, 0, 0, 2, 3, "", {})), nullptr);                 // size 0
  EXPECT_EQ(rx.feed(fragment(7, 2500, 2400, 2, 3, "", pattern(101))), nullptr);  // beyond the size
  EXPECT_EQ(rx.feed(fragment(8, 2500, 5, 0, 3, "CMD", pattern(10)), kB), nullptr);  // fragment 0 not at 0
  EXPECT_EQ(rx.drops(Drop::BadFragment), 5u);
  EXPECT_EQ(rx.feed(fragment(7, 2500, 2000, 2, 4, "", pattern(500))), nullptr);  // count changed mid-message
  EXPECT_EQ(rx.drops(Drop::Inconsistent), 1u);
  const Message* m = rx.feed(fr[2]);  // the message survived all of it
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(Bytes(m->data, m->data + m->size), msg);
}

TEST(UdpmReassembler, SizeAndFragmentCountBeyondTheLimitsAreRefusedBeforeAnyCopy) {
  ReassemblyLimits l;
  l.max_message_bytes = 4096;
  l.max_fragments = 8;
  Rx rx(l);
  EXPECT_EQ(rx.feed(fragment(1, 4097, 0, 0, 2, "CMD", pattern(100))), nullptr);
  EXPECT_EQ(rx.feed(fragment(1, 0xFFFFFFFFu, 0, 0, 2, "CMD", pattern(100))), nullptr);
  EXPECT_EQ(rx.feed(fragment(1, 4096, 0, 0, 9, "CMD", pattern(100))), nullptr);
  EXPECT_EQ(rx.feed(fragment(1, 4096, 0, 0, 65535, "CMD", pattern(100))), nullptr);
  EXPECT_EQ(rx.drops(Drop::TooLarge), 4u);
  EXPECT_EQ(rx.r.partialsInFlight(), 0);
}

TEST(UdpmReassembler, OverlappingFragmentsThatLeaveAHoleAreDropped) {
  Rx rx;
  EXPECT_EQ(rx.feed(fragment(1, 300, 0, 0, 3, "CMD", pattern(100))), nullptr);
  EXPECT_EQ(rx.feed(fragment(1, 300, 50, 1, 3, "", pattern(100))), nullptr);   // overlaps 50..100
  EXPECT_EQ(rx.feed(fragment(1, 300, 200, 2, 3, "", pattern(100))), nullptr);  // 150..200 never written
  // (the lengths add up to the size: only the tiling check sees the hole)
  EXPECT_EQ(rx.drops(Drop::Inconsistent), 1u);
  EXPECT_EQ(rx.r.counters().messages, 0u);
  EXPECT_EQ(rx.r.partialsInFlight(), 0);
}

TEST(UdpmReassembler, ChannelsNotSubscribedAreNeverReassembled) {
  Rx rx;
  for (const Bytes& f : fragmentsOf("NOT_OURS", pattern(3000), 1000)) EXPECT_EQ(rx.feed(f), nullptr);
  EXPECT_EQ(rx.drops(Drop::NotSubscribed), 1u);  // fragment 0
  EXPECT_EQ(rx.drops(Drop::Orphan), 3u);         // the rest find no message
  EXPECT_EQ(rx.r.partialsInFlight(), 0);
}

TEST(UdpmReassembler, ANewMessageFromTheSameSenderSupersedesItsPartialOne) {
  Rx rx;
  const std::vector<Bytes> a = fragmentsOf("CMD", pattern(2500, 1), 1000, 10);
  const std::vector<Bytes> b = fragmentsOf("CMD", pattern(2500, 2), 1000, 11);
  EXPECT_EQ(rx.feed(a[0]), nullptr);
  EXPECT_EQ(rx.feed(b[0]), nullptr);
  EXPECT_EQ(rx.drops(Drop::Superseded), 1u);
  // A late fragment of seqno 10: as in LCM, the sender's newest datagram
  // decides, so 11 is abandoned in turn and the fragment has no message.
  EXPECT_EQ(rx.feed(a[1]), nullptr);
  EXPECT_EQ(rx.drops(Drop::Superseded), 2u);
  EXPECT_EQ(rx.drops(Drop::Orphan), 1u);
}

TEST(UdpmReassembler, AllBuffersBusyEvictsTheOldestPartialMessage) {
  ReassemblyLimits l;
  l.max_partials = 2;
  Rx rx(l);
  const std::vector<Bytes> a = fragmentsOf("CMD", pattern(2500, 1), 1000);
  const Source s1{1, 1}, s2{2, 2}, s3{3, 3};
  EXPECT_EQ(rx.feed(a[0], s1, 10), nullptr);
  EXPECT_EQ(rx.feed(a[0], s2, 20), nullptr);
  EXPECT_EQ(rx.r.partialsInFlight(), 2);
  EXPECT_EQ(rx.feed(a[0], s3, 30), nullptr);
  EXPECT_EQ(rx.drops(Drop::Evicted), 1u);
  EXPECT_EQ(rx.r.partialsInFlight(), 2);
  EXPECT_EQ(rx.feed(a[1], s1, 31), nullptr);  // s1 was the oldest: gone
  EXPECT_EQ(rx.drops(Drop::Orphan), 1u);
  EXPECT_EQ(rx.feed(a[1], s2, 32), nullptr);
  EXPECT_NE(rx.feed(a[2], s2, 33), nullptr);  // s2 completes
}

TEST(UdpmReassembler, APartialMessageOlderThanTheTimeoutIsDropped) {
  ReassemblyLimits l;
  l.partial_timeout_ns = 1000;
  Rx rx(l);
  const std::vector<Bytes> a = fragmentsOf("CMD", pattern(2500), 1000);
  EXPECT_EQ(rx.feed(a[0], kA, 0), nullptr);
  EXPECT_EQ(rx.feed(a[1], kA, 1000), nullptr);  // exactly at the timeout: still alive
  EXPECT_EQ(rx.drops(Drop::TimedOut), 0u);
  rx.r.expire(1001);  // from the first fragment, however recent the last
  EXPECT_EQ(rx.drops(Drop::TimedOut), 1u);
  EXPECT_EQ(rx.r.partialsInFlight(), 0);
  EXPECT_EQ(rx.feed(a[2], kA, 1002), nullptr);
  EXPECT_EQ(rx.drops(Drop::Orphan), 1u);
}

TEST(UdpmReassembler, FeedAllocatesNothing) {
  ReassemblyLimits l;
  l.max_partials = 2;
  Rx rx(l);
  std::vector<Bytes> traffic = fragmentsOf("CMD", pattern(2500), 1000);
  traffic.push_back(shortMsg("CMD", pattern(49)));
  traffic.push_back(shortMsg("OTHER", pattern(49)));
  traffic.push_back(fragment(1, 0xFFFFFFFFu, 0, 0, 2, "CMD", pattern(10)));
  traffic.push_back(Bytes{1, 2});
  ASSERT_GE(test::probeAllocations(), 1);
  const long long before = test::g_allocations.load();
  long long delivered = 0;
  for (int round = 0; round < 50; ++round) {
    for (std::size_t i = 0; i < traffic.size(); ++i) {
      const Source s{static_cast<std::uint32_t>(round % 3), 9};
      delivered += rx.feed(traffic[i], s, round * 1000000000LL) != nullptr;
    }
  }
  EXPECT_EQ(test::g_allocations.load() - before, 0);
  EXPECT_EQ(delivered, 100);  // per round: the reassembled message and the short one
}

}  // namespace
}  // namespace gimbalsim::lcm_wire
