// Contact law of the clearance joint: Hertz normal force with hysteresis
// damping (paper eq. 10-11) and modified Coulomb friction (paper eq. 12).
#pragma once

#include <cmath>

#include "gimbalsim/dynamics/model.hpp"

namespace gimbalsim {

/// delta^n, with the common n = 1.5 done without pow().
inline double hertzPower(double delta, double n) {
  return n == 1.5 ? delta * std::sqrt(delta) : std::pow(delta, n);
}

/// v0 of an end not in contact: a stage of a sub-step that crosses into the
/// bearing before the onset is located (the sub-step is taken back).
constexpr double kOnsetNotLocated = -1.0;

/// Normal force F_n = K delta^n (1 + chi d(delta)/dt / v0) for delta > 0, else
/// 0, never negative (no adhesion). delta [m], vn = d(delta)/dt [m/s], v0 the
/// impact velocity [m/s], floored at c.v0_min. With kOnsetNotLocated the
/// stage's own |vn| is its onset speed: the previous impact's v0 (or 0, the
/// floor) would scale the damping by an unrelated speed, and a small floor
/// made that stage's force overflow before the locator could retake it.
inline double normalForce(const ContactParams& c, double delta, double vn, double v0) {
  if (!(delta > 0.0)) return 0.0;
  double f = c.K * hertzPower(delta, c.exponent);
  if (c.damping != DampingLaw::None) {
    f *= 1.0 + c.chi * vn / std::fmax(v0 == kOnsetNotLocated ? std::fabs(vn) : v0, c.v0_min);
  }
  return f > 0.0 ? f : 0.0;
}

/// Ambrosio's dynamic correction coefficient c_d from |v_t| (never signed).
inline double frictionCorrection(const ContactParams& c, double vt_abs) {
  if (c.friction != FrictionLaw::Ambrosio) return 1.0;
  if (vt_abs <= c.v_a) return 0.0;
  if (vt_abs >= c.v_b) return 1.0;
  return (vt_abs - c.v_a) / (c.v_b - c.v_a);
}

/// Tangential force F_t = -mu c_d F_n sign(v_t) (paper eq. 12) [N].
inline double frictionForce(const ContactParams& c, double fn, double vt) {
  if (c.friction == FrictionLaw::None || vt == 0.0) return 0.0;
  const double mag = c.mu * frictionCorrection(c, std::fabs(vt)) * fn;
  return vt > 0.0 ? -mag : mag;
}

/// Hysteresis factor chi of D = chi K delta^n / v0 for each damping law.
inline double dampingFactor(DampingLaw law, double ce) {
  switch (law) {
    case DampingLaw::HuntCrossley: return 1.5 * (1.0 - ce);
    case DampingLaw::LankaraniNikravesh: return 0.75 * (1.0 - ce * ce);
    case DampingLaw::Flores: return 8.0 * (1.0 - ce) / (5.0 * ce);
    case DampingLaw::None: break;
  }
  return 0.0;
}

}  // namespace gimbalsim
