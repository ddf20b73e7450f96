// LCM's UDP datagrams built byte by byte from the wire format (udpm_util.h of
// LCM 1.3.1: big-endian; LC02 short messages, LC03 fragments), independently
// of the parser under test. Used by the reassembler's unit tests and by the
// HIL attacker (tests/hil/hil_attack.cpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "gimbalsim/lcm_wire/udpm_reassembler.hpp"

namespace gimbalsim::lcm_wire::datagrams {

using Bytes = std::vector<std::uint8_t>;

inline void put32(Bytes& b, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) b.push_back(static_cast<std::uint8_t>(v >> s));
}

inline void put16(Bytes& b, std::uint16_t v) {
  b.push_back(static_cast<std::uint8_t>(v >> 8));
  b.push_back(static_cast<std::uint8_t>(v));
}

/// LC02: magic, seq, the channel (NUL-terminated unless `terminate` is
/// false, a malformed datagram), the payload.
inline Bytes shortMessage(const std::string& ch, const Bytes& payload, std::uint32_t seq = 1, bool terminate = true) {
  Bytes b;
  put32(b, kMagicShort);
  put32(b, seq);
  b.insert(b.end(), ch.begin(), ch.end());
  if (terminate) b.push_back(0);
  b.insert(b.end(), payload.begin(), payload.end());
  return b;
}

/// LC03: magic, seq, message size, this fragment's offset, fragment number
/// and count; fragment 0 then carries the NUL-terminated channel; the data.
inline Bytes fragment(std::uint32_t seq, std::uint32_t size, std::uint32_t offset, std::uint16_t no,
                      std::uint16_t count, const std::string& ch, const Bytes& data) {
  Bytes b;
  put32(b, kMagicFragment);
  put32(b, seq);
  put32(b, size);
  put32(b, offset);
  put16(b, no);
  put16(b, count);
  if (no == 0) {
    b.insert(b.end(), ch.begin(), ch.end());
    b.push_back(0);
  }
  b.insert(b.end(), data.begin(), data.end());
  return b;
}

}  // namespace gimbalsim::lcm_wire::datagrams
