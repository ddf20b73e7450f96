// libFuzzer target: the network receive path (lcm_wire::Reassembler) fed a
// sequence of datagrams from several sources over time. Input: records of
// [u16 length][u8 source][u8 time step] + length bytes. Checks, beyond the
// sanitizers: a delivered message is within the limits, on a subscribed
// channel, and a reassembled one has exactly its declared size; the buffers
// in flight never exceed the bound; every datagram is accounted for.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "gimbalsim/lcm_wire/udpm_reassembler.hpp"

namespace bio = gimbalsim::lcm_wire;

#define FUZZ_CHECK(c) \
  do {                \
    if (!(c)) std::abort(); \
  } while (0)

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  bio::ReassemblyLimits lim;
  lim.max_message_bytes = 4096;
  lim.max_partials = 3;
  lim.max_fragments = 16;
  lim.partial_timeout_ns = 1000;
  static bio::ChannelFilter* filter = new bio::ChannelFilter({"GIMBAL_COMMAND", "C"});
  bio::Reassembler r(lim, *filter);
  std::int64_t now = 0;
  std::uint64_t fed = 0, delivered = 0;
  std::size_t pos = 0;
  while (pos + 4 <= size) {
    const std::size_t len = (std::size_t{data[pos]} << 8 | data[pos + 1]);
    const bio::Source src{data[pos + 2] & 3u, 7};
    now += data[pos + 3] * 10;
    pos += 4;
    const std::size_t n = len < size - pos ? len : size - pos;
    // A copy of exactly n bytes, so ASan sees any read beyond the datagram.
    std::uint8_t* d = static_cast<std::uint8_t*>(std::malloc(n ? n : 1));
    if (n) std::memcpy(d, data + pos, n);
    pos += n;
    const bio::Message* m = r.feed(d, n, src, now);
    ++fed;
    if (m != nullptr) {
      ++delivered;
      FUZZ_CHECK(m->size <= lim.max_message_bytes);
      FUZZ_CHECK(m->channel == "GIMBAL_COMMAND" || m->channel == "C");
      FUZZ_CHECK(m->source == src);
      if (m->size > 0) {
        volatile std::uint8_t sink = m->data[0] ^ m->data[m->size - 1];  // the bytes are readable
        (void)sink;
      }
      if (m->fragmented) {
        std::uint32_t declared = 0;
        std::memcpy(&declared, d + 8, 4);
        FUZZ_CHECK(__builtin_bswap32(declared) == m->size);
      }
    }
    FUZZ_CHECK(r.partialsInFlight() <= lim.max_partials);
    std::free(d);
  }
  FUZZ_CHECK(r.counters().datagrams == fed);
  FUZZ_CHECK(r.counters().messages == delivered);
  return 0;
}
