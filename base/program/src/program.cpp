#include "gimbalsim/program/program.hpp"

#include <cmath>
#include <cstdlib>
#include <limits>

#include "gimbalsim/program/version.hpp"

namespace gimbalsim::program {

namespace {

// CLI11's Range, PositiveNumber and NonNegativeNumber let NaN through (NaN
// compares false with every bound): a value given to a floating-point option
// of any program is a finite number, checked here once for all of them.
std::string nonFiniteOption(const CLI::App& app) {
  for (const CLI::Option* opt : app.get_options()) {
    if (opt->get_type_name().find("FLOAT") == std::string::npos) continue;
    for (const std::string& r : opt->results()) {
      char* end = nullptr;
      const double x = std::strtod(r.c_str(), &end);
      if (end != r.c_str() && !std::isfinite(x)) return opt->get_name() + ": '" + r + "' is not a finite number";
    }
  }
  for (const CLI::App* sub : app.get_subcommands()) {
    if (std::string why = nonFiniteOption(*sub); !why.empty()) return why;
  }
  return "";
}

}  // namespace

std::optional<int> parse(CLI::App& app, int argc, char** argv, const char* program) {
  // Every program's --version: the one string of version.hpp, as "<program> <version>".
  app.set_version_flag("--version", std::string(program) + " " + kVersion);
  try {
    app.parse(argc, argv);
    if (const std::string why = nonFiniteOption(app); !why.empty()) {
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

int refuse(const char* program, const InputError& e) {
  for (const std::string& p : e.problems()) std::fprintf(stderr, "error: %s\n", p.c_str());
  std::fprintf(stderr, "%s: refused, nothing run\n", program);
  return kRefused;
}

}  // namespace gimbalsim::program
