// Cubic Hermite interpolation of a switch function (the contact gap, or the
// tangential velocity) over a sub-step from its values and rates at both
// ends: a cheap first guess of where it crosses zero, and its largest value
// in between. Pure arithmetic; no dynamics is evaluated.
#pragma once

#include <cmath>
#include <initializer_list>

namespace gimbalsim {

/// Root in (0, h) of the cubic Hermite interpolant of the penetration through
/// (0, g0, r0) and (h, g1, r1) (g0, g1 of opposite sides), or -1.
inline double hermiteGapRoot(double h, double g0, double r0, double g1, double r1) {
  auto g = [&](double x) {
    const double t = x / h, t2 = t * t, t3 = t2 * t;
    return (2 * t3 - 3 * t2 + 1) * g0 + (t3 - 2 * t2 + t) * h * r0 + (-2 * t3 + 3 * t2) * g1 + (t3 - t2) * h * r1;
  };
  double lo = 0.0, hi = h, glo = g0;
  if (!((g0 > 0.0) != (g1 > 0.0))) return -1.0;
  for (int i = 0; i < 60 && hi - lo > 1e-6 * h; ++i) {  // bisection, no dynamics evaluated
    const double mid = 0.5 * (lo + hi), gm = g(mid);
    if ((gm > 0.0) == (glo > 0.0)) {
      lo = mid;
      glo = gm;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

/// Largest value over [0, h] of the cubic Hermite interpolant of the gap
/// through (0, g0, r0) and (h, g1, r1) (rates r = d(gap)/dt).
inline double hermiteGapMax(double h, double g0, double r0, double g1, double r1) {
  // p(x) = a x^3 + b x^2 + c x + d on x = t / h in [0, 1]
  const double a = 2.0 * g0 + h * r0 - 2.0 * g1 + h * r1;
  const double b = -3.0 * g0 - 2.0 * h * r0 + 3.0 * g1 - h * r1;
  const double c = h * r0;
  auto p = [&](double x) { return ((a * x + b) * x + c) * x + g0; };
  double best = std::fmax(g0, g1);
  // p'(x) = 3a x^2 + 2b x + c
  const double qa = 3.0 * a, qb = 2.0 * b;
  if (qa == 0.0) {
    if (qb != 0.0) {
      const double x = -c / qb;
      if (x > 0.0 && x < 1.0) best = std::fmax(best, p(x));
    }
    return best;
  }
  const double disc = qb * qb - 4.0 * qa * c;
  if (disc < 0.0) return best;
  // The roots as q / qa and c / q: (-qb +- sqrt(disc)) / (2 qa) loses the
  // small root to cancellation when qa is round-off next to qb, and that root
  // is the maximum of a symmetric approach and recession (a graze).
  const double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
  if (q == 0.0) return best;  // qb = c = 0: p' = qa x^2, no interior extremum
  for (const double x : {q / qa, c / q}) {
    if (x > 0.0 && x < 1.0) best = std::fmax(best, p(x));
  }
  return best;
}

}  // namespace gimbalsim
