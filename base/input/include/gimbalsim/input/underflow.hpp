// The one rule for a number too small for a double: its text names a
// non-zero value that the parse lost. Header-only: the fuzz targets' readers use it.
#pragma once

#include <cfloat>
#include <cmath>
#include <string>

namespace gimbalsim {

/// True when `text` (a decimal) names a non-zero number that its parse `x`
/// lost: 1e-400 reads as 0, 4e-320 as a subnormal with its digits gone.
/// 0 often means "off" or "run forever": a value nobody wrote.
inline bool underflowed(const std::string& text, double x) {
  if (x != 0.0) return std::fabs(x) < DBL_MIN;
  return text.substr(0, text.find_first_of("eE")).find_first_of("123456789") != std::string::npos;
}

}  // namespace gimbalsim
