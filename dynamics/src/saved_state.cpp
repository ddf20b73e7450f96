#include "gimbalsim/dynamics/saved_state.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "gimbalsim/dynamics/variant.hpp"

namespace gimbalsim {

namespace {

std::string num(double x) {
  std::ostringstream o;
  o.precision(17);
  o << x;
  return o.str();
}

struct Shape {
  bool floating = false;
  ClearanceKind kind[2] = {ClearanceKind::Ideal, ClearanceKind::Ideal};
  int group[2] = {0, 0};  ///< first chain index of each joint's group
  int nq = 0, nv = 0, nc = 0;
};

/// The shape a variant name stands for (variantName's spelling, or the one
/// before both joints were named alike) and its name now; false if none.
bool shapeOf(const std::string& name, Shape& out, std::string& canonical) {
#define GIMBALSIM_SHAPE_NAMED(FL, K1, K2, FR)                                                            \
  if (name == shapeName(FL, ClearanceKind::K1, ClearanceKind::K2, FR) ||                                 \
      name == legacyShapeName(FL, ClearanceKind::K1, ClearanceKind::K2, FR)) {                           \
    using V = GIMBALSIM_SHAPE(FL, K1, K2, FR);                                                            \
    out = {FL, {ClearanceKind::K1, ClearanceKind::K2}, {V::G1, V::G2}, V::NQ, V::NV, V::NC};             \
    canonical = shapeName(FL, ClearanceKind::K1, ClearanceKind::K2, FR);                                  \
    return true;                                                                                         \
  }
  GIMBALSIM_FOR_EACH_SHAPE(GIMBALSIM_SHAPE_NAMED)
#undef GIMBALSIM_SHAPE_NAMED
  return false;
}

}  // namespace

std::vector<std::string> savedStateProblems(const SavedState& s, const Model* m) {
  std::vector<std::string> bad;
  auto refuse = [&](const std::string& field, const std::string& why) { bad.push_back("State." + field + " " + why); };
  auto finite = [&](const std::string& field, double x) {
    if (std::isfinite(x)) return true;
    refuse(field, "= " + num(x) + ": must be finite");
    return false;
  };

  Shape shape;
  std::string variant;
  if (!shapeOf(s.variant, shape, variant)) {
    refuse("variant", "'" + s.variant + "': not a variant (e.g. fixed_ideal_planar_friction)");
  } else if (m && variant != variantName(*m)) {
    refuse("variant", "'" + s.variant + "': this simulator runs variant " + variantName(*m));
  }
  if (finite("t", s.t)) {
    if (s.t < 0.0) refuse("t", "= " + num(s.t) + " s: must be >= 0");
    if (m && m->integrator.step > 0.0 && s.t / m->integrator.step > static_cast<double>(kMaxRestoredStepIndex)) {
      refuse("t", "= " + num(s.t) + " s: beyond what the step counter reaches with sim.step = " +
                      num(m->integrator.step) + " s (at most 2^50 steps, t <= " +
                      num(static_cast<double>(kMaxRestoredStepIndex) * m->integrator.step) + " s)");
    }
  }
  const bool sized = !shape.nq || (s.q.size() == static_cast<std::size_t>(shape.nq) &&
                                   s.v.size() == static_cast<std::size_t>(shape.nv));
  if (!sized) {
    refuse("q", "and State.v hold " + std::to_string(s.q.size()) + " and " + std::to_string(s.v.size()) +
                    " values; variant " + s.variant + " has " + std::to_string(shape.nq) + " and " +
                    std::to_string(shape.nv));
  }
  bool all_finite = true;
  for (std::size_t i = 0; i < s.q.size(); ++i) all_finite &= finite("q[" + std::to_string(i) + "]", s.q[i]);
  for (std::size_t i = 0; i < s.v.size(); ++i) all_finite &= finite("v[" + std::to_string(i) + "]", s.v[i]);
  if (shape.nq && sized && all_finite) {
    if (shape.floating) {
      // q[3..6] is the base attitude quaternion: a rotation only at unit norm.
      const double norm = std::sqrt(s.q[3] * s.q[3] + s.q[4] * s.q[4] + s.q[5] * s.q[5] + s.q[6] * s.q[6]);
      if (!(std::fabs(norm - 1.0) <= 1e-9)) {
        refuse("q[3:7]", "(base attitude quaternion) has norm " + num(norm) + ": must be 1");
      }
    }
    const int qj = shape.floating ? 7 : 0;
    for (int j = 0; j < 2; ++j) {
      if (shape.kind[j] == ClearanceKind::Ideal) continue;
      const std::string joint = " (joint " + std::to_string(j + 1) + ")";
      const int g = qj + shape.group[j];
      // The journal centre (ecc) stays inside the bearing; beyond its radius
      // the contact law has no meaning.
      const double ecc = std::hypot(s.q[g], s.q[g + 1]);
      if (m && !(ecc <= m->bearing[j].bearing_radius)) {
        refuse("q", "holds |ecc| = " + num(ecc) + " m" + joint + ": beyond the bearing radius " +
                        num(m->bearing[j].bearing_radius) + " m");
      }
      // A spatial journal's axis must cross the bearing's end planes.
      if (shape.kind[j] == ClearanceKind::Spatial && !(std::cos(s.q[g + 2]) * std::cos(s.q[g + 3]) >= 0.5)) {
        refuse("q", "holds a tilt alpha = " + num(s.q[g + 2]) + ", beta = " + num(s.q[g + 3]) + " rad" + joint +
                        ": beyond 60 degrees, no bearing allows it");
      }
    }
  }
  if (shape.nq && (s.in_contact.size() != static_cast<std::size_t>(shape.nc) ||
                   s.v0.size() != static_cast<std::size_t>(shape.nc))) {
    refuse("in_contact", "and State.v0 hold " + std::to_string(s.in_contact.size()) + " and " +
                             std::to_string(s.v0.size()) + " values; variant " + s.variant + " has " +
                             std::to_string(shape.nc) + " contact ends");
  }
  for (std::size_t i = 0; i < s.v0.size(); ++i) finite("v0[" + std::to_string(i) + "]", s.v0[i]);
  if (finite("vt_floor", s.vt_floor) && s.vt_floor > 0.0) {
    refuse("vt_floor", "= " + num(s.vt_floor) + " m/s: must be <= 0");
  }
  if (s.friction_mode < -1 || s.friction_mode > 1) {
    refuse("friction_mode", "= " + std::to_string(s.friction_mode) + ": must be -1, 0 or 1");
  }
  if (finite("h_next", s.h_next)) {
    if (s.h_next < 0.0) refuse("h_next", "= " + num(s.h_next) + " s: must be >= 0 (0: none chosen yet)");
    if (m && s.h_next != 0.0 &&
        !(s.h_next >= m->integrator.substep_min && s.h_next <= m->integrator.step)) {
      refuse("h_next", "= " + num(s.h_next) + " s: must be 0 or in [sim.substep_min, sim.step] = [" +
                           num(m->integrator.substep_min) + ", " + num(m->integrator.step) + "] s");
    }
  }
  return bad;
}

void checkSavedState(const SavedState& s, const Model* m) {
  const std::vector<std::string> bad = savedStateProblems(s, m);
  if (bad.empty()) return;
  std::string text;
  for (const std::string& b : bad) text += (text.empty() ? "" : "\n") + b;
  throw std::invalid_argument(text);
}

}  // namespace gimbalsim
