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

std::optional<unsigned> unprintableAt(const std::string& s, std::size_t i, std::size_t* bytes) {
  // Only a well-formed sequence is decoded: pass 103's first try read 0xE2 and any two bytes as U+2xxx.
  const auto at = [&](std::size_t k) { return k < s.size() ? static_cast<unsigned char>(s[k]) : 0u; };
  const auto continuation = [](unsigned b) { return b >= 0x80 && b <= 0xBF; };
  *bytes = 1;
  if (i >= s.size()) return std::nullopt;
  if ((at(i) < 0x20 && at(i) != '\t') || at(i) == 0x7F) return at(i);
  unsigned cp = 0;
  if (at(i) == 0xC2 && at(i + 1) >= 0x80 && at(i + 1) <= 0x9F) {  // C1: U+0080..9F
    *bytes = 2;
    return at(i + 1);
  }
  if (at(i) == 0xD8 && at(i + 1) == 0x9C) {
    cp = 0x061C;
  } else if (at(i) == 0xE2 && continuation(at(i + 1)) && continuation(at(i + 2))) {  // U+2000..2FFF
    cp = 0x2000u + ((at(i + 1) & 0x3Fu) << 6) + (at(i + 2) & 0x3Fu);
  }
  if (!isLayoutCodePoint(cp)) return std::nullopt;
  *bytes = cp == 0x061C ? 2 : 3;
  return cp;
}

std::string shownText(const std::string& s) {
  // (pass 103, 107) an unknown key or a refused value holding U+202E (from a quoted scalar's escape) was printed
  // raw: the rest of the terminal's line ran backwards from it
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    std::size_t bytes = 1;
    if (const auto cp = unprintableAt(s, i, &bytes)) {
      char code[12];
      std::snprintf(code, sizeof code, "<U+%04X>", *cp);
      out += code;
      i += bytes - 1;
    } else {
      out += s[i];
    }
  }
  return out;
}

}  // namespace gimbalsim
