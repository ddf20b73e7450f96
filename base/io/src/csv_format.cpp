#include "gimbalsim/io/csv_format.hpp"

#include <charconv>

namespace gimbalsim::io {

std::string csvName(std::string_view name, std::string_view unit) {
  std::string out(name);
  if (unit.empty() || unit == "-") return out;
  out += '_';
  // Every unit of the key tables reads as an identifier: "N m/(rad s)" -> Nm_per_rad_s.
  int depth = 0;  // inside parentheses a space separates factors of one denominator
  for (char c : unit) {
    const bool word = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9');
    if (c == '/') {
      out += "_per_";
    } else if (c == '(' || c == ')') {
      depth += c == '(' ? 1 : -1;
    } else if (word) {
      out += c;
    } else if (c != '^' && (c != ' ' || depth > 0) && out.back() != '_') {
      out += '_';  // any other character: a separator, never kept
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

std::string csvTextCell(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case ',': out += ';'; break;
      case '"': out += '\''; break;
      case '#': out += "no. "; break;
      case '\n': case '\r': out += ' '; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace gimbalsim::io
