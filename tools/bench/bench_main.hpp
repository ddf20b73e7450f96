// The main of the Google Benchmark programs: --version as every program of
// the project answers it, an unknown flag refused (exit 2), the library's
// flags read as the programs read theirs (benchmarkFlagProblem), a crash
// reported as the others report one (program::guardedMain).
#pragma once

#include <benchmark/benchmark.h>

#include <cstdio>
#include <set>
#include <string>

#include "gimbalsim/input/plain_decimal.hpp"
#include "gimbalsim/input/value_format.hpp"
#include "gimbalsim/program/program.hpp"
#include "gimbalsim/program/version.hpp"

namespace gimbalsim::bench {

/// The first problem of Google Benchmark's flags, or "": each given once and something after its '=', its
/// numbers plain decimals in range. The library keeps the last of two (pass 78: a second --benchmark_filter won),
/// takes "0x1" and "010" (ten repetitions) and "nan" (--benchmark_min_time=nan never ends).
inline std::string benchmarkFlagProblem(int argc, char** argv) {
  struct Number {
    const char* name;
    double lo, hi;
    bool whole;
  };
  static const Number kNumbers[] = {{"--benchmark_min_time", 1e-6, 1e4, false},
                                    {"--benchmark_min_warmup_time", 0.0, 1e4, false},
                                    {"--benchmark_repetitions", 1.0, 1e6, true},
                                    {"--benchmark_v", 0.0, 10.0, true}};
  std::set<std::string> given;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.rfind("--benchmark_", 0) != 0) continue;
    const std::size_t eq = arg.find('=');
    const std::string flag = arg.substr(0, eq);
    if (!given.insert(flag).second) return flag + ": given twice; it takes one value";
    if (eq != std::string::npos && eq + 1 == arg.size()) return flag + ": an empty value after the '='";
    for (const Number& n : kNumbers) {
      if (flag != n.name) continue;
      const std::string text = eq == std::string::npos ? "" : arg.substr(eq + 1);
      double x = 0.0;
      const bool plain = readPlainDecimal(text, x) == DecimalProblem::None && !hasLeadingZero(text) &&
                         (!n.whole || text.find_first_not_of("+0123456789") == std::string::npos);
      if (!plain || x < n.lo || x > n.hi) {
        return flag + ": must be a " + (n.whole ? "whole number" : "plain decimal number") + " in [" +
               formatNumber(n.lo) + ", " + formatNumber(n.hi) + "] after its '=', got '" + text + "'";
      }
    }
  }
  return {};
}

inline int benchmarkMain(const char* name, int argc, char** argv) {
  return program::guardedMain(name, [&] {
    for (int i = 1; i < argc; ++i) {
      if (std::string(argv[i]) == "--version") {
        std::printf("%s %s\n", name, program::kVersion);
        return static_cast<int>(program::kOk);
      }
    }
    if (const std::string why = benchmarkFlagProblem(argc, argv); !why.empty()) return program::refuse(name, why);
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return static_cast<int>(program::kRefused);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return static_cast<int>(program::kOk);
  });
}

}  // namespace gimbalsim::bench
