// Converters from a YAML value (value_convert.hpp).
#include "gimbalsim/input/value_convert.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>

#include "gimbalsim/input/underflow.hpp"

namespace gimbalsim {

namespace {

/// What a value is, for a refusal that says what it got, also when that is nothing or no scalar.
std::string got(const YAML::Node& n) {
  if (n.IsScalar()) return "'" + shownText(n.Scalar()) + "'";
  return n.IsMap() ? "a map" : n.IsSequence() ? "a list" : "no value";
}

}  // namespace

double asNumber(const YAML::Node& n) {
  if (!n.IsScalar()) throw ConvertError{"expected a number, got " + got(n)};
  double x;
  if (!YAML::convert<double>::decode(n, x)) throw ConvertError{"expected a number, got " + got(n)};
  if (!std::isfinite(x)) throw ConvertError{"must be finite, got " + got(n)};
  if (underflowed(n.Scalar(), x)) {
    throw ConvertError{"'" + shownText(n.Scalar()) +
                       "' underflows a double: give a magnitude of at least 2.2e-308, or 0 where the key takes it"};
  }
  return x;
}

int asInt(const YAML::Node& n) {
  // Digits only: "1e3" and "5.0" are a float's spelling, which no integer key is written in.
  const std::string& t = n.IsScalar() ? n.Scalar() : std::string();
  const std::size_t sign = !t.empty() && (t[0] == '+' || t[0] == '-') ? 1 : 0;
  if (sign == t.size() || t.find_first_not_of("0123456789", sign) != std::string::npos) {
    throw ConvertError{"expected a whole number (digits only), got " + got(n)};
  }
  const double x = asNumber(n);
  if (std::fabs(x) > 1e9) throw ConvertError{"must be a whole number within [-1e9, 1e9], got " + got(n)};
  return static_cast<int>(x);
}

template <int N>
Eigen::Matrix<double, N, 1> asVector(const YAML::Node& n, const char* expected) {
  if (!n.IsSequence() || static_cast<int>(n.size()) != N) {
    throw ConvertError{expected ? std::string("expected ") + expected
                                : "expected a list of " + std::to_string(N) + " numbers"};
  }
  Eigen::Matrix<double, N, 1> v;
  for (int i = 0; i < N; ++i) v(i) = asNumber(n[i]);
  return v;
}
template Eigen::Vector2d asVector<2>(const YAML::Node&, const char*);
template Eigen::Vector3d asVector<3>(const YAML::Node&, const char*);

Mat3 asInertia(const YAML::Node& n) {
  Mat3 I = Mat3::Zero();
  if (n.IsSequence() && n.size() == 3 && n[0].IsSequence()) {
    for (int r = 0; r < 3; ++r) {
      if (!n[r].IsSequence() || n[r].size() != 3) throw ConvertError{"expected a 3x3 matrix"};
      for (int c = 0; c < 3; ++c) I(r, c) = asNumber(n[r][c]);
    }
    return I;
  }
  if (n.IsSequence() && n.size() == 3) {
    I.diagonal() = asVector<3>(n);
    return I;
  }
  if (n.IsSequence() && n.size() == 6) {
    const auto v = asVector<6>(n);
    I << v(0), v(3), v(4), v(3), v(1), v(5), v(4), v(5), v(2);
    return I;
  }
  throw ConvertError{"expected [Ixx, Iyy, Izz], [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] or a 3x3 matrix"};
}

std::string asString(const YAML::Node& n) {
  if (!n.IsScalar()) throw ConvertError{"expected a string"};
  // The file's bytes are checked as text, but a quoted scalar's escapes ("\e]0;x\a", "\u0000") make control
  // characters after it: printed raw they set a terminal's title or cleared it, a NUL cut the name (pass 86).
  const std::string& s = n.Scalar();
  for (std::size_t i = 0; i < s.size(); ++i) {
    // (pass 94, 97) and U+2028/2029 that split a printed line, the bidi controls that reorder it
    std::size_t bytes = 1;
    if (const auto cp = unprintableAt(s, i, &bytes)) {
      char code[8];
      std::snprintf(code, sizeof code, "%04X", *cp);
      throw ConvertError{"character U+" + std::string(code) + " (a control character, from an escape) at position " +
                         std::to_string(i) + ": no text a name or label holds"};
    }
  }
  return s;
}

std::size_t asChoice(const YAML::Node& n, const std::vector<std::string>& names) {
  const std::string s = n.IsScalar() ? n.Scalar() : std::string();
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (s == names[i]) return i;
  }
  // what it got, also when that is nothing (pass 40: '' said only what was expected)
  throw ConvertError{"expected one of " + join(names, " | ") + ", got " + got(n)};
}

}  // namespace gimbalsim
