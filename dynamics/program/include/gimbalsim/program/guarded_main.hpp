// The outermost frame of a gimbalsim program's main(): an exception that
// escaped the program's own handling (a bug, or memory exhausted) becomes one
// line naming the program and exit code 1, instead of std::terminate.
#pragma once

#include <cstdio>
#include <exception>

namespace gimbalsim {

template <class Body>
int guardedMain(const char* program, Body&& body) noexcept {
  try {
    return body();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: internal error: %s\n", program, e.what());
  } catch (...) {
    std::fprintf(stderr, "%s: internal error (unknown exception)\n", program);
  }
  return 1;
}

}  // namespace gimbalsim
