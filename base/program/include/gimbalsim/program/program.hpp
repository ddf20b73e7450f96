// The one program entry. Why it exists: every program used to repeat its own
// CLI11 block and its own exit codes, and CLI11's codes leaked out (an unknown
// flag gave 106, a bad value 104). Here, once for all of them: the exit-code
// table of docs/usage.md "Exit codes", the parse (--help -> 0, any refused
// argument -> "<program>: error: <what>" and 2), the refusal of an input, and
// the outermost guard of main() (an escaped exception -> one line and 1).
//
//   int mainImpl(int argc, char** argv) {
//     CLI::App app{"..."};  // options
//     if (const auto rc = gimbalsim::program::parse(app, argc, argv, "name")) return *rc;
//     ...  // a gimbalsim::InputError thrown here is refused with 2 by the guard
//   }
//   int main(int argc, char** argv) {
//     return gimbalsim::program::guardedMain("name", [&] { return mainImpl(argc, argv); });
//   }
#pragma once

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>
#include <exception>
#include <new>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gimbalsim/input/input_error.hpp"
#include "gimbalsim/input/plain_decimal.hpp"
#include "gimbalsim/program/stop_signal.hpp"

namespace gimbalsim::program {

/// The exit codes of every program (docs/usage.md "Exit codes").
enum Exit : int {
  kOk = 0,        ///< success
  kInternal = 1,  ///< a bug, memory exhausted (the guard)
  kRefused = 2,   ///< bad arguments, scene, configuration, fault schedule, log or spec: nothing run
  kStopped = 3,   ///< the run stopped (numerical trouble, a plant stop); outputs whole up to it
  kOutput = 4,    ///< an output file could not be written; nothing under its name
  kNetwork = 5,   ///< LCM or the network could not start, or failed
  kNoPeer = 6,    ///< no peer: no plant within --idle-exit, the plant gone (--plant-timeout), no controller within
                  ///< --start-timeout; (Python) no Dask scheduler or worker at --scheduler
  kPartial = 7,   ///< the input was cut short (a truncated log): every whole part converted, the cut reported
  kNotReproduced = 8,  ///< a replay differs from its record (gimbalsim.sweep --replay, _errors.py; torque_replay: a stop)
};
/// Stopped by signal N (outputs whole): 128 + N, i.e. 130 for SIGINT, 143 for SIGTERM.
constexpr int signalExit(int signal) { return 128 + signal; }

/// Parses argv into app (adding --version: "<program> <kVersion>", version.hpp).
/// nullopt: go on. Otherwise the code main() returns:
/// kOk after --help or --version (printed on stdout), kRefused after any refused argument
/// (unknown flag, bad or missing value, failed check, a NaN or infinite number), printed on stderr as
/// "<program>: error: <what> (see --help)".
std::optional<int> parse(CLI::App& app, int argc, char** argv, const char* program);

/// A CLI11 check for an integer option, put before its CLI::Range: a range
/// check alone calls "1.5" or "abc" out of range instead of not whole.
inline CLI::Validator wholeNumber() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        std::size_t i = s.size() > 1 && (s[0] == '-' || s[0] == '+') ? 1 : 0;
        if (i == s.size()) return "'" + s + "' is not a whole number";
        // CLI11 then reads '010' as octal 8 (pass 36: --truth-csv every 8 ticks for 010)
        if (hasLeadingZero(s)) return "'" + s + "' is not a whole number written without a leading zero";
        for (; i < s.size(); ++i) {
          if (s[i] < '0' || s[i] > '9') return "'" + s + "' is not a whole number";
        }
        return {};
      },
      "INT");
}

/// A CLI11 check for a real option: in [lo, hi], or in (lo, hi] when
/// above_lo, said plainly ("--rate: must be > 0 and at most 1e+06, got 0").
/// (parse() also refuses anything but a plain finite decimal number.)
CLI::Validator within(double lo, double hi, bool above_lo = false);
/// within(lo, hi), or exactly 0 (a wait's "never"): "must be 0 or in [0.1, 1e+09], got 1e-300".
CLI::Validator zeroOrWithin(double lo, double hi);

/// "<program>: error: <what>" and "<program>: refused, nothing run" on stderr; kRefused.
int refuse(const char* program, const std::string& what);
/// An output whose path is allowed but whose file cannot be made (a read-only
/// or full folder), before anything ran: "<program>: error: <what>" and
/// "<program>: the output cannot be written, nothing run" on stderr; kOutput.
int unwritable(const char* program, const std::string& what);
/// Every problem as "error: <problem>", then "<program>: refused, nothing run"; kRefused.
int refuse(const char* program, const InputError& e);

/// A program's key=value overrides (--scene-set) against the keys it sets itself, each with the flag that
/// sets it ({"sim.duration", "--duration"}): "" when none is given, else the refusal naming the first
/// override (#k) and the flag to use (a given sim.duration was replaced by the program's own, silently).
std::string overrideOfOwnKey(const char* flag, const std::vector<std::string>& overrides,
                             const std::vector<std::pair<std::string, std::string>>& own);

/// A list flag's values (a run or a row per value): "" when none repeats, else "<flag>: <value> given twice"
/// (pass 73, pass 76: `--omega 10,10.0` ran one bandwidth twice, two identical rows). Numbers are one value
/// when equal as doubles (1e-4 and 0.0001); a list flag given twice is one list.
std::string repeatedValue(const char* flag, const std::vector<double>& values);
std::string repeatedValue(const char* flag, const std::vector<std::string>& values);

/// Opens /dev/null on each of stdin, stdout and stderr that is closed: a
/// program started with `>&-` would otherwise give descriptor 1 or 2 to the
/// first file it opens (an output's temporary), and its console lines would
/// be written into that output. With them open, the lines are dropped.
void keepStandardStreams() noexcept;

/// The outermost frame of main(): body()'s code; an InputError (or a
/// CLI::ParseError) that escaped is refused (kRefused); any other exception
/// is a bug or exhausted memory: "<program>: internal error: ..." and kInternal.
template <class Body>
int guardedMain(const char* program, Body&& body) noexcept {
  keepStandardStreams();
  // A file-size limit (ulimit -f) must fail a write (EFBIG: exit 4, temporaries removed), not
  // kill the program with SIGXFSZ and leave them behind; Python ignores it the same way.
  std::signal(SIGXFSZ, SIG_IGN);
  // A console whose reader is gone (`2>&1 | head -1`) must not kill the run (exit 141, outputs cut): its
  // lines fail with EPIPE and are dropped, and the exit code is the run's (docs/usage.md "Exit codes").
  std::signal(SIGPIPE, SIG_IGN);
  try {
    try {
      return body();
    } catch (const InputError& e) {
      return refuse(program, e);
    } catch (const CLI::ParseError& e) {
      return refuse(program, e.what());
    }
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "%s: internal error: memory exhausted\n", program);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: internal error: %s\n", program, e.what());
  } catch (...) {
    std::fprintf(stderr, "%s: internal error (unknown exception)\n", program);
  }
  return kInternal;
}

}  // namespace gimbalsim::program
