// The compiled shapes of a scene (Variant) and the one switch from a Model
// to its shape: every caller that runs a Model picks its Variant here, once.
#pragma once

#include <string>

#include "gimbalsim/dynamics/model.hpp"

namespace gimbalsim {

/// Chain coordinates of a joint of this kind (its group): ideal [theta],
/// planar [p_x, p_y, theta], spatial [p_x, p_y, alpha, beta, theta].
constexpr int groupSize(ClearanceKind k) {
  return k == ClearanceKind::Ideal ? 1 : k == ClearanceKind::Planar ? 3 : 5;
}
/// Contact ends of a joint of this kind: none, the one planar contact, the
/// spatial bearing's two end planes.
constexpr int contactEnds(ClearanceKind k) {
  return k == ClearanceKind::Ideal ? 0 : k == ClearanceKind::Planar ? 1 : 2;
}

/// Compile-time shape of a scene: base, the kind of each joint, friction. A
/// variant without a floating base, contact or friction compiles none of
/// their code.
template <bool Floating, ClearanceKind K1, ClearanceKind K2, bool Friction>
struct Variant {
  static constexpr bool kFloating = Floating;
  static constexpr ClearanceKind kKind1 = K1, kKind2 = K2;
  static constexpr bool kFriction = Friction;
  static constexpr int N1 = groupSize(K1), N2 = groupSize(K2);  ///< chain coordinates per joint
  static constexpr int G1 = 0, G2 = N1;          ///< first chain index of each joint's group
  static constexpr int NC = contactEnds(K1) + contactEnds(K2);  ///< contact ends
  static constexpr bool kContact = NC > 0;       ///< any clearance joint
  static constexpr int NB = Floating ? 6 : 0;    ///< base velocity coordinates
  static constexpr int NJ = N1 + N2;             ///< 1-dof joints of the chain
  static constexpr int NV = NB + NJ;             ///< velocity coordinates
  static constexpr int NQ = (Floating ? 7 : 0) + NJ;  ///< position coordinates
  static_assert(kContact || !Friction, "friction needs a clearance joint");
  /// The kind and the group offset of joint j (0: azimuth, 1: elevation).
  static constexpr ClearanceKind kind(int j) { return j == 0 ? K1 : K2; }
  static constexpr int group(int j) { return j == 0 ? G1 : G2; }
  /// Chain index of joint j's angle theta_j: the last of its group.
  static constexpr int theta(int j) { return j == 0 ? N1 - 1 : NJ - 1; }
  /// Contact ends: joint 1's first, a spatial joint's s = -1 then s = +1.
  static constexpr int firstEnd(int j) { return j == 0 ? 0 : contactEnds(K1); }
  static constexpr int endJoint(int e) { return e < contactEnds(K1) ? 0 : 1; }
  /// friction.law coulomb_stick (set-valued friction with located stick/slip)
  /// is built for one planar contact: a planar joint 2 with an ideal joint 1.
  static constexpr bool kStick =
      Friction && K1 == ClearanceKind::Ideal && K2 == ClearanceKind::Planar;
};

using FixedIdeal = Variant<false, ClearanceKind::Ideal, ClearanceKind::Ideal, false>;
using FixedClearance = Variant<false, ClearanceKind::Ideal, ClearanceKind::Planar, false>;
using FixedClearanceFriction = Variant<false, ClearanceKind::Ideal, ClearanceKind::Planar, true>;
using FloatingIdeal = Variant<true, ClearanceKind::Ideal, ClearanceKind::Ideal, false>;
using FloatingClearance = Variant<true, ClearanceKind::Ideal, ClearanceKind::Planar, false>;
using FloatingClearanceFriction = Variant<true, ClearanceKind::Ideal, ClearanceKind::Planar, true>;

/// "ideal", "planar" or "spatial", as the scene keys structure.joint1/2 name it.
const char* kindName(ClearanceKind k);
/// The name of a shape: floating|fixed, each joint's kind (joint 1's, then
/// joint 2's), _friction (e.g. floating_ideal_planar_friction, fixed_spatial_spatial).
std::string shapeName(bool floating, ClearanceKind k1, ClearanceKind k2, bool friction);
/// The name before both joints were named alike (floating_clearance_friction,
/// fixed_spatial1_spatial): still read from a saved state.
std::string legacyShapeName(bool floating, ClearanceKind k1, ClearanceKind k2, bool friction);
/// Which compiled variant a model runs as.
std::string variantName(const Model& m);
/// Friction code is compiled in only when it can act.
inline bool frictionActive(const Model& m) {
  const auto acts = [](const ContactParams& c) { return c.friction != FrictionLaw::None && c.mu > 0.0; };
  return (m.joint1_kind != ClearanceKind::Ideal && acts(m.bearing[0])) ||
         (m.joint2_kind != ClearanceKind::Ideal && acts(m.bearing[1]));
}

/// Every compiled shape, X(floating, kind 1, kind 2, friction): both bases,
/// each pair of joint kinds, with and without friction where there is
/// contact (2 x (1 + 8 x 2) = 34). The one list behind the dispatch below and
/// the explicit instantiations of the step (dynamics/src/shapes.inc, one
/// build file per pair of joint kinds).
#define GIMBALSIM_CONTACT_SHAPES(X, FL, FR)                                                              \
  X(FL, Ideal, Planar, FR) X(FL, Ideal, Spatial, FR) X(FL, Planar, Ideal, FR) X(FL, Planar, Planar, FR) \
  X(FL, Planar, Spatial, FR) X(FL, Spatial, Ideal, FR) X(FL, Spatial, Planar, FR) X(FL, Spatial, Spatial, FR)
#define GIMBALSIM_FOR_EACH_SHAPE(X)                                                                       \
  X(true, Ideal, Ideal, false) X(false, Ideal, Ideal, false) GIMBALSIM_CONTACT_SHAPES(X, true, false)    \
  GIMBALSIM_CONTACT_SHAPES(X, true, true) GIMBALSIM_CONTACT_SHAPES(X, false, false)                      \
  GIMBALSIM_CONTACT_SHAPES(X, false, true)
#define GIMBALSIM_SHAPE(FL, K1, K2, FR) ::gimbalsim::Variant<FL, ::gimbalsim::ClearanceKind::K1, ::gimbalsim::ClearanceKind::K2, FR>

/// Calls f with a default-constructed Variant tag matching the model (every
/// shape of GIMBALSIM_FOR_EACH_SHAPE; f's result type must not depend on it).
template <class F>
decltype(auto) dispatchVariant(const Model& m, F&& f) {
  const bool friction = frictionActive(m);
  using R = decltype(f(FloatingIdeal{}));
#define GIMBALSIM_DISPATCH_ONE(FL, K1, K2, FR)                                                       \
  if (m.floating_base == FL && m.joint1_kind == ClearanceKind::K1 && m.joint2_kind == ClearanceKind::K2 && \
      (friction == FR || !GIMBALSIM_SHAPE(FL, K1, K2, FR)::kContact))                                  \
    return static_cast<R>(f(GIMBALSIM_SHAPE(FL, K1, K2, FR){}));
  GIMBALSIM_FOR_EACH_SHAPE(GIMBALSIM_DISPATCH_ONE)
#undef GIMBALSIM_DISPATCH_ONE
  return static_cast<R>(f(FloatingIdeal{}));  // not reached: every kind pair is listed
}

}  // namespace gimbalsim
