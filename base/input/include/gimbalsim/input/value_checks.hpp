// The checks a key's value must pass: the rule in words for the key tables
// and the test, shared by every key table.
#pragma once

#include <functional>
#include <span>
#include <string>
#include <utility>

namespace gimbalsim {

/// A key's own check, on every component of its value.
struct Check {
  std::string rule;  ///< in words for the tables ("> 0", "in (0, 1]"); "" = none
  std::string says;  ///< the refusal; "" = "must be <rule>"
  std::function<bool(std::span<const double>)> holds;

  Check saying(std::string s) const {
    Check c = *this;
    c.says = std::move(s);
    return c;
  }
  std::string refusal() const { return says.empty() ? "must be " + rule : says; }
};
Check greater(double lo);                                     ///< "> lo"
Check atLeast(double lo);                                     ///< ">= lo"
Check interval(char open, double lo, double hi, char close);  ///< "in (lo, hi]" etc.
Check nonZero();                                              ///< |v| >= 1e-12
Check positiveDefinite();                                     ///< a symmetric positive definite 3x3

}  // namespace gimbalsim
