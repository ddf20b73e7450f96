// How values are written back in messages and key tables: numbers that read
// back exactly (shortest round-trip form), lists, inertias, whole-multiple hints.
#include <charconv>
#include <cmath>
#include <cstdio>

#include "gimbalsim/input/value_format.hpp"

namespace gimbalsim {

std::string formatNumber(double x) {
  char b[32];
  const auto r = std::to_chars(b, b + sizeof b, x);
  return std::string(b, r.ptr);
}

std::string formatSignificant(double x, int digits) {
  char b[64];
  std::snprintf(b, sizeof b, "%.*g", digits, x);
  return b;
}

bool isWholeMultiple(double value, double unit) {
  const double n = value / unit;
  return std::isfinite(n) && std::round(n) >= 1.0 && std::fabs(n - std::round(n)) <= 1e-12 * n;
}

std::string wholeMultipleProblem(double value, double unit, const std::string& unit_name) {
  const double n = value / unit;
  // A count past 1e12 is no run anyone waits for, and llround of it is undefined.
  if (!(std::abs(n) <= 1e12)) return "must be at most 1e12 times " + unit_name + " (" + formatNumber(unit) + " s)";
  if (isWholeMultiple(value, unit)) return "";
  auto multiple = [&](double k) {
    char b[32];
    std::snprintf(b, sizeof b, "%.12g", k * unit);
    return std::string(b);
  };
  const std::string what = "must be a whole multiple of " + unit_name + " (" + formatNumber(unit) + " s), at least one";
  if (std::isfinite(n) && n > 1.0) return what + "; the nearest: " + multiple(std::floor(n)) + " or " + multiple(std::floor(n) + 1.0);
  return what + "; the shortest: " + multiple(1.0);
}

std::string formatList(std::span<const double> v) {
  std::vector<std::string> parts;
  for (double x : v) parts.push_back(formatNumber(x));
  return "[" + join(parts, ", ") + "]";
}

std::string formatInertia(const Mat3& I) {
  if (I.isDiagonal(0.0)) {
    const Eigen::Vector3d d = I.diagonal();
    return formatList({d.data(), 3});
  }
  if (I == I.transpose()) {
    const double v[6] = {I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2)};
    return formatList(v);
  }
  std::vector<std::string> rows;
  for (int r = 0; r < 3; ++r) {
    const Eigen::Vector3d row = I.row(r).transpose();
    rows.push_back(formatList({row.data(), 3}));
  }
  return "[" + join(rows, ", ") + "]";
}

std::string join(const std::vector<std::string>& parts, const std::string& sep) {
  std::string out;
  for (std::size_t i = 0; i < parts.size(); ++i) out += (i ? sep : "") + parts[i];
  return out;
}

bool isLayoutCodePoint(unsigned cp) {
  return cp == 0x0085 || cp == 0x061C || cp == 0x200E || cp == 0x200F || (cp >= 0x2028 && cp <= 0x202E) ||
         (cp >= 0x2066 && cp <= 0x2069);
}

std::size_t utf8At(const std::string& s, std::size_t i, unsigned* cp) {
  // Only a well-formed sequence is decoded: pass 103's first try read 0xE2 and any two bytes as U+2xxx.
  const auto at = [&](std::size_t k) { return k < s.size() ? static_cast<unsigned char>(s[k]) : 0u; };
  const unsigned b = at(i);
  const std::size_t n = i >= s.size() ? 0
                        : b < 0x80         ? 1
                        : (b >> 5) == 0x6  ? 2
                        : (b >> 4) == 0xE  ? 3
                        : (b >> 3) == 0x1E ? 4
                                           : 0;
  if (n == 0 || i + n > s.size()) return 0;
  unsigned c = n == 1 ? b : n == 2 ? (b & 0x1Fu) : n == 3 ? (b & 0x0Fu) : (b & 0x07u);
  for (std::size_t k = 1; k < n; ++k) {
    if ((at(i + k) & 0xC0u) != 0x80u) return 0;
    c = (c << 6) | (at(i + k) & 0x3Fu);
  }
  static constexpr unsigned kLeast[5] = {0, 0, 0x80, 0x800, 0x10000};  // a shorter form is not UTF-8
  if (c < kLeast[n] || c > 0x10FFFF || (c >= 0xD800 && c <= 0xDFFF)) return 0;
  *cp = c;
  return n;
}

std::optional<unsigned> unprintableAt(const std::string& s, std::size_t i, std::size_t* bytes) {
  unsigned cp = 0;
  *bytes = 1;
  const std::size_t n = utf8At(s, i, &cp);
  if (n == 0) return std::nullopt;
  *bytes = n;
  const bool control = (cp < 0x20 && cp != '\t') || (cp >= 0x7F && cp <= 0x9F);  // C0 but tab, DEL, C1
  if (control || isLayoutCodePoint(cp)) return cp;
  return std::nullopt;
}

std::string shownText(const std::string& s, bool tab_shown) {
  // (pass 103, 107) an unknown key or a refused value holding U+202E (from a quoted scalar's escape) was printed
  // raw: the rest of the terminal's line ran backwards from it; (pass 113) a log's channel name, anyone's bytes,
  // printed 0x9B (CSI to an 8-bit terminal) raw: a byte that is not UTF-8 is shown as <0xHH>
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    std::size_t bytes = 1;
    unsigned cp = 0;
    char code[12] = "";
    if (const auto c = unprintableAt(s, i, &bytes); c || (tab_shown && s[i] == '\t')) {
      std::snprintf(code, sizeof code, "<U+%04X>", c ? *c : 0x09u);
    } else if (utf8At(s, i, &cp) == 0) {
      std::snprintf(code, sizeof code, "<0x%02X>", static_cast<unsigned char>(s[i]));
    }
    out += code[0] != '\0' ? std::string(code) : s.substr(i, bytes);
    i += bytes - 1;
  }
  return out;
}

}  // namespace gimbalsim
