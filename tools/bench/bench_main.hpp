// The main of the Google Benchmark programs: --version as every program of
// the project answers it, an unknown flag refused (exit 2), the library's
// flags read as the programs read theirs (benchmarkFlagProblem), a crash
// reported as the others report one (program::guardedMain).
#pragma once

#include <benchmark/benchmark.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "gimbalsim/input/plain_decimal.hpp"
#include "gimbalsim/input/value_format.hpp"
#include "gimbalsim/io/output_file.hpp"
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
                                    {"--v", 0.0, 10.0, true}};
  struct Choice {
    const char* name;
    std::vector<const char*> values;
    bool bare_is_true;  ///< a bool flag: given without '=' it is true
  };
  static const std::vector<Choice> kChoices = {
      {"--benchmark_format", {"console", "json", "csv"}, false},
      {"--benchmark_out_format", {"console", "json", "csv"}, false},
      {"--benchmark_time_unit", {"ns", "us", "ms", "s"}, false},
      {"--benchmark_color", {"true", "false", "auto"}, true},
      {"--benchmark_counters_tabular", {"true", "false"}, true},
      {"--benchmark_enable_random_interleaving", {"true", "false"}, true},
      {"--benchmark_report_aggregates_only", {"true", "false"}, true},
      {"--benchmark_display_aggregates_only", {"true", "false"}, true},
      {"--benchmark_list_tests", {"true", "false"}, true}};
  // Debian's Google Benchmark 1.7's flags, as its --help lists them (pass 95: --v=abc and a word that is no flag
  // got the library's "unrecognized" under the program's full path; --benchmark_dry_run is a later version's)
  static const std::set<std::string> kFlags = {
      "--benchmark_list_tests", "--benchmark_filter", "--benchmark_min_time", "--benchmark_min_warmup_time",
      "--benchmark_repetitions", "--benchmark_enable_random_interleaving", "--benchmark_report_aggregates_only",
      "--benchmark_display_aggregates_only", "--benchmark_format", "--benchmark_out", "--benchmark_out_format",
      "--benchmark_color", "--benchmark_counters_tabular", "--benchmark_context", "--benchmark_time_unit", "--v",
      "--help"};
  std::set<std::string> given;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const std::size_t eq = arg.find('=');
    const std::string flag = arg.substr(0, eq);
    // (pass 95) counters were taken and the library aborted (SIGABRT): it is built without libpfm
    if (flag == "--benchmark_perf_counters") {
      return flag + ": this build's Google Benchmark (Debian's libbenchmark) counts no performance counters";
    }
    if (!kFlags.count(flag)) {
      return "'" + arg + "': not a flag of this program (Google Benchmark's flags, as --help lists them, and "
             "--version)";
    }
    if (!given.insert(flag).second) return flag + ": given twice; it takes one value";
    const bool bare_bool = std::any_of(kChoices.begin(), kChoices.end(),
                                       [&](const Choice& c) { return flag == c.name && c.bare_is_true; });
    if (eq == std::string::npos && !bare_bool && flag != "--help") return flag + ": takes a value after its '='";
    if (eq != std::string::npos && eq + 1 == arg.size()) return flag + ": an empty value after the '='";
    const std::string value = eq == std::string::npos ? "" : arg.substr(eq + 1);
    // (pass 91) a value outside a choice printed the usage and exited 0 with nothing run, a bool took any word
    for (const Choice& c : kChoices) {
      if (flag != c.name || (c.bare_is_true && eq == std::string::npos)) continue;
      if (std::find(c.values.begin(), c.values.end(), value) == c.values.end()) {
        std::string list;
        for (const char* v : c.values) list += (list.empty() ? "" : ", ") + std::string(v);
        return flag + ": must be one of " + list + " after its '=', got '" + value + "'";
      }
    }
    if (flag == "--benchmark_context") {  // (pass 93) an empty key or item, a key twice were taken or "unrecognized"
      std::set<std::string> keys;
      std::stringstream items(value);
      std::string item;
      while (std::getline(items, item, ',')) {
        const std::size_t at = item.find('=');
        if (at == std::string::npos || at == 0 || !keys.insert(item.substr(0, at)).second) {
          return flag + ": must be KEY=VALUE[,KEY=VALUE...], each KEY once and not empty, got '" + value + "'";
        }
      }
      if (keys.empty() || value.back() == ',') {
        return flag + ": must be KEY=VALUE[,KEY=VALUE...], each KEY once and not empty, got '" + value + "'";
      }
    }
    if (flag == "--benchmark_filter") {  // (pass 93) '[' printed "Could not compile", ran nothing and exited 0
      try {
        std::regex(value, std::regex::extended);
      } catch (const std::regex_error& e) {
        return flag + ": '" + value + "' is not a regular expression (" + e.what() + ")";
      }
    }
    for (const Number& n : kNumbers) {
      if (flag != n.name) continue;
      const std::string& text = value;
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

/// --benchmark_out=PATH by the writer's rules (pass 86: the library wrote through a link, over a scene the
/// benchmarks read, over the program itself, and left a file behind a refused run): the library writes a private
/// temporary, copied onto PATH through io::OutputFile (checked before any benchmark runs) when the run ends.
class BenchmarkOut {
 public:
  /// Rewrites argv's --benchmark_out to the temporary; throws io::OutputError for a PATH the rules refuse.
  BenchmarkOut(int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      if (arg.rfind("--benchmark_out=", 0) != 0) continue;
      std::vector<std::string> inputs;  // the scenes the benchmarks load: $GIMBALSIM_SCENE_DIR, else tools/scenes
      const char* scenes = std::getenv("GIMBALSIM_SCENE_DIR");
      std::error_code ec;
      for (const auto& e : std::filesystem::directory_iterator(scenes && *scenes ? scenes : "tools/scenes", ec)) {
        inputs.push_back(e.path());
      }
      out_ = std::make_unique<io::OutputFile>(arg.substr(16), inputs);  // the program itself is always an input
      char name[] = "/tmp/gimbalsim_bench_out.XXXXXX";
      const int fd = mkstemp(name);
      if (fd < 0) throw io::OutputError("a temporary for --benchmark_out: cannot be made in /tmp", true);
      close(fd);
      temporary_ = name;
      flag_ = "--benchmark_out=" + temporary_;
      argv[i] = flag_.data();
    }
  }
  ~BenchmarkOut() {
    if (!temporary_.empty()) std::remove(temporary_.c_str());
  }
  BenchmarkOut(const BenchmarkOut&) = delete;
  BenchmarkOut& operator=(const BenchmarkOut&) = delete;

  /// After the run: the library's file onto PATH ("" when done or not asked), or why not. No benchmark run
  /// writes nothing (the library left an empty file, read as a result).
  std::string publish(std::size_t ran) {
    if (!out_) return {};
    if (ran == 0) return "no benchmark ran: " + out_->path() + " not written";
    std::ifstream in(temporary_, std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    if (!in || !out_->write(bytes.str()) || !out_->commit()) {
      return out_->error().empty() ? out_->path() + ": cannot be written" : out_->error();
    }
    return {};
  }

 private:
  std::unique_ptr<io::OutputFile> out_;
  std::string temporary_, flag_;
};

/// The benchmarks that failed (their rows say ERROR OCCURRED): the run ends with the first one's code, never 0
/// (pass 117: rows of errors exited 0). A scene that does not load is thrown instead: refused (exit 2).
struct Failures {
  int count = 0;
  int code = 0;
  std::string first;
};
inline Failures& failures() {
  static Failures f;
  return f;
}
inline void fail(benchmark::State& bs, const std::string& why, program::Exit code) {
  Failures& f = failures();
  if (f.count++ == 0) {
    f.code = code;
    f.first = why;
  }
  bs.SkipWithError(why.c_str());
}

/// Whether the run's --benchmark_filter selects the benchmark `full_name` (Google Benchmark's rule: an extended
/// regular expression searched in the name, a leading '-' negating it; none or "all": every one).
inline bool filterSelects(int argc, char** argv, const std::string& full_name) {
  std::string filter = "all";
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]).rfind("--benchmark_filter=", 0) == 0) filter = std::string(argv[i]).substr(19);
  }
  if (filter.empty() || filter == "all") return true;
  const bool negative = filter[0] == '-';
  return std::regex_search(full_name, std::regex(negative ? filter.substr(1) : filter, std::regex::extended)) !=
         negative;
}

/// prepare(argc, argv): run before any benchmark, after the flags are read; what it throws (a scene that does not
/// load) refuses the run before anything runs (pass 119: bench_tick ran its LCM parts, then refused).
inline int benchmarkMain(const char* name, int argc, char** argv,
                         const std::function<void(int, char**)>& prepare = {}) {
  return program::guardedMain(name, [&] {
    for (int i = 1; i < argc; ++i) {
      if (std::string(argv[i]) == "--version") {
        std::printf("%s %s\n", name, program::kVersion);
        return static_cast<int>(program::kOk);
      }
    }
    if (const std::string why = benchmarkFlagProblem(argc, argv); !why.empty()) return program::refuse(name, why);
    std::unique_ptr<BenchmarkOut> out;
    try {
      out = std::make_unique<BenchmarkOut>(argc, argv);
    } catch (const io::OutputError& e) {
      return e.unwritable() ? program::unwritable(name, e.what()) : program::refuse(name, e.what());
    }
    // --help and --benchmark_list_tests run no benchmark: they need no scene
    const bool runs = std::none_of(argv + 1, argv + argc, [](const char* a) {
      const std::string arg = a;
      return arg.rfind("--help", 0) == 0 || arg == "--benchmark_list_tests" || arg == "--benchmark_list_tests=true";
    });
    if (prepare && runs) prepare(argc, argv);
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return static_cast<int>(program::kRefused);
    const std::size_t ran = benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    if (const std::string why = out->publish(ran); !why.empty()) {
      std::fprintf(stderr, "%s: %s\n", name, why.c_str());
      if (ran > 0) return static_cast<int>(program::kOutput);
    }
    if (const Failures& f = failures(); f.count > 0) {
      std::fprintf(stderr, "%s: %d benchmark%s failed (ERROR OCCURRED above), the first: %s\n", name, f.count,
                   f.count == 1 ? "" : "s", f.first.c_str());
      return f.code;
    }
    // (pass 95) a filter that matched none ran nothing and exited 0, as if measured; run_bench.sh refused it
    if (ran == 0) return program::refuse(name, "--benchmark_filter matched none of this program's benchmarks");
    return static_cast<int>(program::kOk);
  });
}

}  // namespace gimbalsim::bench
