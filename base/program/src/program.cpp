#include "gimbalsim/program/program.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "gimbalsim/input/plain_decimal.hpp"
#include "gimbalsim/input/value_format.hpp"
#include "gimbalsim/program/version.hpp"

namespace gimbalsim::program {

void keepStandardStreams() noexcept {
  for (int fd = 0; fd <= 2; ++fd) {
    if (fcntl(fd, F_GETFD) != -1 || errno != EBADF) continue;
    const int null_fd = open("/dev/null", O_RDWR | O_CLOEXEC);  // the lowest free descriptor: fd itself
    if (null_fd >= 0 && null_fd != fd) {
      dup2(null_fd, fd);  // dup2 clears close-on-exec on fd: a child inherits it open
      close(null_fd);
    } else if (null_fd == fd) {
      fcntl(fd, F_SETFD, 0);  // inherited open by the programs this one starts
    }
  }
}

namespace {

// Why a value given to a floating-point option is not a plain finite decimal
// number ("" when it is). CLI11 converts "0x1p-13", " 5" and an empty list
// item ("1e-4,,2e-4") and lets NaN through every range: checked here once,
// for every FLOAT option of every program.
std::string notPlainReal(const std::string& r, bool in_list) {
  double x = 0.0;
  switch (readPlainDecimal(r, x)) {
    // as an INT flag refuses it (pass 42: --duration 010 ran 10 s where --truth-every 010 was refused)
    case DecimalProblem::None: return hasLeadingZero(r) ? "'" + r + "' is not a number written without a leading zero" : "";
    // the list's hint only for a list (pass 44: a scalar's '' was asked about commas)
    case DecimalProblem::Empty: return in_list ? "an empty value (two commas in a row, or one at the end?)"
                                               : "an empty value";
    case DecimalProblem::NotDecimal: return "'" + r + "' is not a decimal number";
    case DecimalProblem::NotFinite: return "'" + r + "' is not a finite number";
    // 1e-400 reads as 0, which a duration takes for "run until stopped": a number too small is refused.
    case DecimalProblem::Underflow: return "'" + r + "' is too small for a double (it would be read as 0 or lose its digits)";
  }
  return "";
}

// An empty text value ('--summary ""') was taken as "no such output" (nothing written, exit 0) or
// as the current folder: a value given must say something.
std::string emptyTextOption(const CLI::App& app) {
  for (const CLI::Option* opt : app.get_options()) {
    if (opt->get_type_name().find("TEXT") == std::string::npos) continue;
    for (const std::string& r : opt->results()) {
      if (r.empty()) return opt->get_name() + ": an empty value (a path or a name is needed)";
      // Only blanks: a file named '  ' is a slip of the shell, never a name anyone means.
      if (r.find_first_not_of(" \t\r\n") == std::string::npos) {
        return opt->get_name() + ": a blank value '" + r + "' (a path or a name is needed)";
      }
    }
  }
  for (const CLI::App* sub : app.get_subcommands()) {
    if (std::string why = emptyTextOption(*sub); !why.empty()) return why;
  }
  return "";
}

std::string badRealOption(const CLI::App& app) {
  for (const CLI::Option* opt : app.get_options()) {
    if (opt->get_type_name().find("FLOAT") == std::string::npos) continue;
    for (const std::string& r : opt->results()) {
      if (std::string why = notPlainReal(r, opt->get_items_expected_max() > 1); !why.empty()) {
        return opt->get_name() + ": " + why;
      }
    }
  }
  for (const CLI::App* sub : app.get_subcommands()) {
    if (std::string why = badRealOption(*sub); !why.empty()) return why;
  }
  return "";
}

// CLI11 drops the empty items of a delimited list ("--omega 5,,10" runs 5 and
// 10): the raw arguments of such options are checked for one.
std::string emptyListItem(const CLI::App& app, int argc, char** argv) {
  const std::vector<const CLI::App*> apps = [&] {
    std::vector<const CLI::App*> all{&app};
    for (const CLI::App* sub : app.get_subcommands()) all.push_back(sub);  // the ones parsed
    return all;
  }();
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg.rfind("--", 0) != 0) continue;
    const std::size_t eq = arg.find('=');
    const std::string name = arg.substr(0, eq);
    for (const CLI::App* a : apps) {
      const CLI::Option* opt = a->get_option_no_throw(name);
      if (opt == nullptr || opt->get_delimiter() == '\0') continue;
      const std::string value = eq != std::string::npos ? arg.substr(eq + 1) : (k + 1 < argc ? argv[k + 1] : "");
      const std::string d(1, opt->get_delimiter());
      if (value.empty() || value.find(d + d) != std::string::npos || value.front() == d[0] || value.back() == d[0]) {
        return name + ": '" + value + "' has an empty item (two commas in a row, or one at an end)";
      }
    }
  }
  return "";
}

}  // namespace

CLI::Validator within(double lo, double hi, bool above_lo) {
  char text[96];
  std::snprintf(text, sizeof text, above_lo ? "> %g and at most %g" : "in [%g, %g]", lo, hi);
  const std::string range = text;
  return CLI::Validator(
      [=](std::string& s) -> std::string {
        // A number no double holds: 1e-400 reads as 0 and was told "must be > 0" (pass 68)
        if (double y = 0.0; readPlainDecimal(s, y) == DecimalProblem::Underflow) return notPlainReal(s, false);
        char* end = nullptr;
        const double x = std::strtod(s.c_str(), &end);
        if (end == s.c_str()) return "'" + s + "' is not a number";
        if (!std::isfinite(x)) return "'" + s + "' is not a finite number";
        const bool ok = (above_lo ? x > lo : x >= lo) && x <= hi;
        return ok ? std::string() : "must be " + range + ", got " + s;
      },
      "NUMBER " + range);
}

CLI::Validator zeroOrWithin(double lo, double hi) {
  char text[96];
  std::snprintf(text, sizeof text, "0 or in [%g, %g]", lo, hi);
  const std::string range = text;
  const CLI::Validator in_range = within(lo, hi);
  return CLI::Validator(
      [=](std::string& s) -> std::string {
        if (double y = 0.0; readPlainDecimal(s, y) == DecimalProblem::Underflow) return notPlainReal(s, false);
        char* end = nullptr;
        if (std::strtod(s.c_str(), &end) == 0.0 && end != s.c_str() && *end == '\0') return {};
        std::string copy = s;
        const std::string why = in_range(copy);  // "not a number" as within() says it; a range in this one's words
        return why.empty() || why.rfind("must be", 0) != 0 ? why : "must be " + range + ", got " + s;
      },
      "NUMBER " + range);
}

std::optional<int> parse(CLI::App& app, int argc, char** argv, const char* program) {
  // Every program's --version: the one string of version.hpp, as "<program> <version>".
  app.set_version_flag("--version", std::string(program) + " " + kVersion);
  // CLI11 reads '--out=' (nothing after the '=') as '--out' and takes the next argument for its value
  // (pass 36: '--truth-csv= --lockstep' wrote a file named --lockstep and ran in real time).
  for (int k = 1; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "--") break;
    if (arg.size() > 3 && arg.rfind("--", 0) == 0 && arg.find('=') == arg.size() - 1) {
      std::fprintf(stderr, "%s: error: %s: an empty value after the '=' (see --help)\n", program, arg.c_str());
      return kRefused;
    }
  }
  try {
    app.parse(argc, argv);
    std::string why = emptyListItem(app, argc, argv);
    if (why.empty()) why = badRealOption(app);
    if (why.empty()) why = emptyTextOption(app);
    if (!why.empty()) {
      std::fprintf(stderr, "%s: error: %s (see --help)\n", program, why.c_str());
      return kRefused;
    }
    return std::nullopt;
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) {  // --help, --help-all, --version
      app.exit(e);  // prints the help of the (sub)command asked, on stdout
      return kOk;
    }
    // CLI11's NonNegativeNumber/PositiveNumber print their bound, DBL_MAX, in 309 digits.
    std::string what = e.what();
    const std::string dbl_max = std::to_string(std::numeric_limits<double>::max());
    if (const auto at = what.find(dbl_max); at != std::string::npos) what.replace(at, dbl_max.size(), "inf");
    // CLI11 checks what is required before what is unknown: `gimbalsim --bogus`
    // would say only "A subcommand is required", `simulate S --bogus` only that
    // --out is required. The unknown argument comes first (a subcommand's too).
    if (dynamic_cast<const CLI::RequiredError*>(&e) != nullptr) {
      if (const std::vector<std::string> extra = app.remaining(true); !extra.empty()) {
        what = "The following argument was not expected: " + extra.front() + "; " + what;
      }
    }
    std::fprintf(stderr, "%s: error: %s (see --help)\n", program, what.c_str());
    return kRefused;
  }
}

int refuse(const char* program, const std::string& what) {
  std::fprintf(stderr, "%s: error: %s\n%s: refused, nothing run\n", program, what.c_str(), program);
  return kRefused;
}

int unwritable(const char* program, const std::string& what) {
  std::fprintf(stderr, "%s: error: %s\n%s: the output cannot be written, nothing run\n", program, what.c_str(), program);
  return kOutput;
}

int refuse(const char* program, const InputError& e) {
  for (const std::string& p : e.problems()) std::fprintf(stderr, "error: %s\n", p.c_str());
  std::fprintf(stderr, "%s: refused, nothing run\n", program);
  return kRefused;
}

std::string overrideOfOwnKey(const char* flag, const std::vector<std::string>& overrides,
                             const std::vector<std::pair<std::string, std::string>>& own) {
  for (std::size_t k = 0; k < overrides.size(); ++k) {
    const std::string key = overrides[k].substr(0, overrides[k].find('='));
    for (const auto& [owned, by] : own) {
      if (key == owned) {
        return std::string(flag) + " #" + std::to_string(k + 1) + " '" + overrides[k] + "': this program sets " +
               key + " itself (" + by + "): give it there";
      }
    }
  }
  return "";
}

namespace {

template <class T, class Name>
std::string firstRepeat(const char* flag, const std::vector<T>& values, Name name) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (values[j] == values[i]) return std::string(flag) + ": " + name(values[i]) + " given twice";
    }
  }
  return "";
}

}  // namespace

std::string repeatedValue(const char* flag, const std::vector<double>& values) {
  return firstRepeat(flag, values, [](double v) { return formatNumber(v); });
}

std::string repeatedValue(const char* flag, const std::vector<std::string>& values) {
  return firstRepeat(flag, values, [](const std::string& v) { return v; });
}

}  // namespace gimbalsim::program
