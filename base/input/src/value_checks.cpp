// The checks a key's value must pass (Check: its rule as text and the test),
// shared by every key table.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "gimbalsim/input/value_checks.hpp"
#include "gimbalsim/input/value_format.hpp"

namespace gimbalsim {

namespace {
Check each(std::string rule, std::function<bool(double)> ok) {
  return {std::move(rule), "", [ok](std::span<const double> v) { return std::all_of(v.begin(), v.end(), ok); }};
}
}  // namespace

Check greater(double lo) {
  return each("> " + formatNumber(lo), [lo](double x) { return x > lo; });
}

Check atLeast(double lo) {
  return each(">= " + formatNumber(lo), [lo](double x) { return x >= lo; });
}

Check interval(char open, double lo, double hi, char close) {
  const std::string rule = "in " + std::string(1, open) + formatNumber(lo) + ", " + formatNumber(hi) + close;
  return each(rule, [=](double x) { return (open == '(' ? x > lo : x >= lo) && (close == ')' ? x < hi : x <= hi); });
}

Check nonZero() {
  // Bounded above too: a length that overflows (1e200 per component)
  // normalises to a zero vector, a direction nobody asked for.
  return {"of length at least 1e-12, each component within 1e12", "", [](std::span<const double> v) {
            double s = 0.0;
            for (double x : v) {
              if (!(std::abs(x) <= 1e12)) return false;
              s += x * x;
            }
            return std::sqrt(s) >= 1e-12;
          }};
}

// Below 1e-6 kg and 1e-9 kg m^2 a body's accelerations overflow under any contact force (1e-100 kg m^2
// ran to a NaN at t = 0 naming no key); no part of a gimbal is that light.
Check bodyMass() { return interval('[', 1e-6, 1e9, ']').saying("mass must be in [1e-6, 1e9] kg"); }

Check bodyOffset() { return interval('[', -1e3, 1e3, ']'); }

Check bodyInertia() {
  const Check pd = positiveDefinite();
  return {"symmetric positive definite, principal moments >= 1e-9, entries within 1e12",
          "inertia must be symmetric positive definite with principal moments of at least 1e-9 kg m^2, each entry "
          "within 1e12 kg m^2",
          [pd](std::span<const double> v) {
            if (!std::all_of(v.begin(), v.end(), [](double x) { return std::abs(x) <= 1e12; }) || !pd.holds(v)) {
              return false;
            }
            return Eigen::SelfAdjointEigenSolver<Mat3>(Eigen::Map<const Mat3>(v.data())).eigenvalues().minCoeff() >=
                   1e-9;
          }};
}

Check positiveDefinite() {
  return {"symmetric positive definite", "", [](std::span<const double> v) {
            const Eigen::Map<const Mat3> I(v.data());
            if (!I.isApprox(I.transpose(), 1e-12)) return false;
            return Eigen::SelfAdjointEigenSolver<Mat3>(I).eigenvalues().minCoeff() > 0.0;
          }};
}

}  // namespace gimbalsim
