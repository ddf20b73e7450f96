#include "gimbalsim/dynamics/variant.hpp"

namespace gimbalsim {

const char* kindName(ClearanceKind k) {
  static const char* const kKind[] = {"ideal", "planar", "spatial"};
  return kKind[static_cast<int>(k)];
}

std::string shapeName(bool floating, ClearanceKind k1, ClearanceKind k2, bool friction) {
  return std::string(floating ? "floating" : "fixed") + "_" + kindName(k1) + "_" + kindName(k2) +
         (friction ? "_friction" : "");
}

std::string legacyShapeName(bool floating, ClearanceKind k1, ClearanceKind k2, bool friction) {
  std::string s = floating ? "floating" : "fixed";
  if (k1 != ClearanceKind::Ideal) s += std::string("_") + kindName(k1) + "1";
  s += k2 == ClearanceKind::Ideal ? "_ideal" : k2 == ClearanceKind::Planar ? "_clearance" : "_spatial";
  if (friction) s += "_friction";
  return s;
}

std::string variantName(const Model& m) {
  return shapeName(m.floating_base, m.joint1_kind, m.joint2_kind, frictionActive(m));
}

}  // namespace gimbalsim
