#include "gimbalsim/io/csv_format.hpp"

#include <charconv>

namespace gimbalsim::io {

std::string csvName(std::string_view name, std::string_view unit) {
  std::string out(name);
  if (unit.empty() || unit == "-") return out;
  out += '_';
  for (char c : unit) {
    if (c == '/') {
      out += "_per_";
    } else if (c != ' ' && c != '^') {
      out += c;
    }
  }
  return out;
}

std::string csvNameOf(std::string_view bracketed) {
  const auto open = bracketed.find('[');
  if (open == std::string_view::npos || bracketed.back() != ']') return std::string(bracketed);
  return csvName(bracketed.substr(0, open), bracketed.substr(open + 1, bracketed.size() - open - 2));
}

int formatCsvNumber(char* buf, double x) noexcept {
  if (x == 0.0) x = 0.0;  // -0 prints as 0
  const auto r = std::to_chars(buf, buf + 32, x);
  return static_cast<int>(r.ptr - buf);
}

void appendCsvNumber(std::string& out, double x) {
  char buf[32];
  out.append(buf, static_cast<std::size_t>(formatCsvNumber(buf, x)));
}

}  // namespace gimbalsim::io
