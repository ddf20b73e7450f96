// The main of the Google Benchmark programs: --version as every program of
// the project answers it, an unknown flag refused (exit 2), a crash reported
// as the others report one (program::guardedMain).
#pragma once

#include <benchmark/benchmark.h>

#include <cstdio>
#include <string>

#include "gimbalsim/program/program.hpp"
#include "gimbalsim/program/version.hpp"

namespace gimbalsim::bench {

inline int benchmarkMain(const char* name, int argc, char** argv) {
  return program::guardedMain(name, [&] {
    for (int i = 1; i < argc; ++i) {
      if (std::string(argv[i]) == "--version") {
        std::printf("%s %s\n", name, program::kVersion);
        return static_cast<int>(program::kOk);
      }
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return static_cast<int>(program::kRefused);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return static_cast<int>(program::kOk);
  });
}

}  // namespace gimbalsim::bench
