// What every loader fuzz target asserts about a refusal: each problem says
// where (the document's origin, a file position, or a --set index) and, when
// it names a key, prints it. A violation aborts, which libFuzzer reports.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>

#include "gimbalsim/dynamics/scene.hpp"

namespace gimbalsim::fuzz {

inline void fail(const char* why, const Problem& p) {
  std::fprintf(stderr, "fuzz check failed: %s\n  problem: %s\n", why, p.text.c_str());
  std::abort();
}

inline void checkRefusal(const SceneError& e, const std::string& origin) {
  if (e.details().empty()) {
    std::fprintf(stderr, "fuzz check failed: a refusal without problems\n");
    std::abort();
  }
  for (const Problem& p : e.details()) {
    if (p.set_index > 0) {
      if (p.text.rfind("--set #" + std::to_string(p.set_index) + " '", 0) != 0) fail("--set place not first", p);
    } else {
      if (p.file != origin || p.text.rfind(origin, 0) != 0) fail("file place not first", p);
      if (p.line > 0 && p.text.rfind(origin + ":" + std::to_string(p.line) + ":", 0) != 0) fail("line not printed", p);
    }
    if (!p.key.empty() && p.text.find("'" + p.key + "'") == std::string::npos) fail("key not printed", p);
  }
}

}  // namespace gimbalsim::fuzz
