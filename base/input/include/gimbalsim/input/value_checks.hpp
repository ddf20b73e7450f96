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
Check nonZero();                                              ///< |v| >= 1e-12, each |v_i| <= 1e12
Check positiveDefinite();                                     ///< a symmetric positive definite 3x3

// A body's mass properties and offsets, for the scene's bodies and the
// controller's plant model alike: ranges whose products (torques, momenta,
// the mass matrix) stay far from overflow, around any satellite's.
Check bodyMass();     ///< [kg] in [1e-6, 1e9]
Check bodyOffset();   ///< [m] each component in [-1e3, 1e3]
Check bodyInertia();  ///< [kg m^2] symmetric positive definite, each entry within 1e12

}  // namespace gimbalsim
