// What every loader fuzz target asserts about a refusal: each problem says
// where (the document's origin, a file position, or a --set index) and, when
// it names a key, prints it. A violation aborts, which libFuzzer reports.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "gimbalsim/input/value_format.hpp"
#include "gimbalsim/scene/scene.hpp"

namespace gimbalsim::fuzz {

/// The documented bounds as libFuzzer flags, placed before the caller's own
/// (a later flag wins): one input may take at most 5 s and the process 512 MB,
/// else libFuzzer reports a timeout or out-of-memory as a failure. Inputs are
/// capped at 64 KiB (the loaders' file bound is 1 MiB; longer adds no paths).
inline int withBounds(int* argc, char*** argv) {
  static std::vector<char*> args;
  static char rss[] = "-rss_limit_mb=512", timeout[] = "-timeout=5", len[] = "-max_len=65536";
  args.assign(*argv, *argv + 1);
  args.insert(args.end(), {rss, timeout, len});
  args.insert(args.end(), *argv + 1, *argv + *argc);
  args.push_back(nullptr);
  *argc = static_cast<int>(args.size()) - 1;
  *argv = args.data();
  return 0;
}

inline void fail(const char* why, const Problem& p) {
  std::fprintf(stderr, "fuzz check failed: %s\n  problem: %s\n", why, p.text.c_str());
  std::abort();
}

inline void checkRefusal(const InputError& e, const std::string& origin) {
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
    // as shownText prints it: a character that splits or reorders the line as <U+XXXX>, every other byte as given
    if (!p.key.empty() && p.text.find("'" + shownText(p.key) + "'") == std::string::npos) fail("key not printed", p);
  }
}

}  // namespace gimbalsim::fuzz
