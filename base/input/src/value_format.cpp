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

}  // namespace gimbalsim
