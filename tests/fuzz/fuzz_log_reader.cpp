// libFuzzer target: the LCM log reader (lcm_wire::LogReader) on arbitrary
// bytes. Checks, beyond the sanitizers: every event lies inside the file, in
// order, and a malformed log stops with an error naming an offset inside it.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "gimbalsim/lcm_wire/lcm_log.hpp"

namespace bio = gimbalsim::lcm_wire;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // A copy of exactly `size` bytes, so ASan sees any read beyond the file.
  std::uint8_t* copy = static_cast<std::uint8_t*>(std::malloc(size ? size : 1));
  if (size) std::memcpy(copy, data, size);
  bio::LogReader r;
  r.openMemory(copy, size);
  bio::LogEvent e;
  std::uint64_t next = 0;
  while (r.next(&e)) {
    if (e.offset != next) std::abort();
    if (e.channel.empty() || e.channel.size() > static_cast<std::size_t>(bio::kMaxLogChannelBytes)) std::abort();
    next = e.offset + bio::kLogHeaderBytes + e.channel.size() + e.size;
    if (next > size) std::abort();
  }
  if (r.error().empty() ? next != size : (r.errorOffset() != next || r.errorOffset() >= size)) std::abort();
  std::free(copy);
  return 0;
}
