// The process's peak resident memory, for the bench programs' exit summaries
// (the HIL attack tests hold it under a stated bound).
#pragma once

#include <cstdio>
#include <cstring>

namespace gimbalsim::lcm_wire {

/// VmHWM from /proc/self/status [kB]; -1 when unavailable.
inline long peakRssKb() noexcept {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (f == nullptr) return -1;
  char line[256];
  long kb = -1;
  while (std::fgets(line, sizeof line, f)) {
    if (std::strncmp(line, "VmHWM:", 6) == 0) {
      std::sscanf(line + 6, "%ld", &kb);
      break;
    }
  }
  std::fclose(f);
  return kb;
}

}  // namespace gimbalsim::lcm_wire
