#include "gimbalsim/program/program.hpp"

#include <limits>

#include "gimbalsim/program/version.hpp"

namespace gimbalsim::program {

std::optional<int> parse(CLI::App& app, int argc, char** argv, const char* program) {
  // Every program's --version: the one string of version.hpp, as "<program> <version>".
  app.set_version_flag("--version", std::string(program) + " " + kVersion);
  try {
    app.parse(argc, argv);
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
