// The compiled shapes of a scene (Variant) and the one switch from a Model
// to its shape: every caller that runs a Model picks its Variant here, once.
#pragma once

#include <string>

#include "gimbalsim/dynamics/model.hpp"

namespace gimbalsim {

/// Compile-time shape of a scene. A variant without a floating base,
/// clearance or friction compiles none of their code.
template <bool Floating, bool Clearance, bool Friction>
struct Variant {
  static_assert(Clearance || !Friction, "friction needs the clearance joint");
  static constexpr bool kFloating = Floating;
  static constexpr bool kClearance = Clearance;
  static constexpr bool kFriction = Friction;
  static constexpr int NB = Floating ? 6 : 0;    ///< base velocity coordinates
  static constexpr int NJ = Clearance ? 4 : 2;   ///< 1-dof joints of the chain
  static constexpr int NV = NB + NJ;             ///< velocity coordinates
  static constexpr int NQ = (Floating ? 7 : 0) + NJ;  ///< position coordinates
};

using FixedIdeal = Variant<false, false, false>;
using FixedClearance = Variant<false, true, false>;
using FixedClearanceFriction = Variant<false, true, true>;
using FloatingIdeal = Variant<true, false, false>;
using FloatingClearance = Variant<true, true, false>;
using FloatingClearanceFriction = Variant<true, true, true>;

/// Which compiled variant a model runs as.
std::string variantName(const Model& m);
/// Friction code is compiled in only when it can act.
inline bool frictionActive(const Model& m) {
  return m.clearance_joint && m.contact.friction != FrictionLaw::None && m.contact.mu > 0.0;
}

/// Calls f with a default-constructed Variant tag matching the model.
template <class F>
decltype(auto) dispatchVariant(const Model& m, F&& f) {
  if (m.floating_base) {
    if (!m.clearance_joint) return f(FloatingIdeal{});
    if (frictionActive(m)) return f(FloatingClearanceFriction{});
    return f(FloatingClearance{});
  }
  if (!m.clearance_joint) return f(FixedIdeal{});
  if (frictionActive(m)) return f(FixedClearanceFriction{});
  return f(FixedClearance{});
}

}  // namespace gimbalsim
