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

/// Which compiled variant a model runs as.
std::string variantName(const Model& m);
/// Friction code is compiled in only when it can act.
inline bool frictionActive(const Model& m) {
  return m.hasClearance() && m.contact.friction != FrictionLaw::None && m.contact.mu > 0.0;
}

/// Calls f with a default-constructed Variant tag matching the model. The
/// shapes compiled so far: joint 1 ideal, joint 2 ideal or planar (the scene
/// loader refuses the others until their contact is built).
template <class F>
decltype(auto) dispatchVariant(const Model& m, F&& f) {
  const bool planar2 = m.joint2_kind == ClearanceKind::Planar;
  if (m.floating_base) {
    if (!planar2) return f(FloatingIdeal{});
    if (frictionActive(m)) return f(FloatingClearanceFriction{});
    return f(FloatingClearance{});
  }
  if (!planar2) return f(FixedIdeal{});
  if (frictionActive(m)) return f(FixedClearanceFriction{});
  return f(FixedClearance{});
}

}  // namespace gimbalsim
