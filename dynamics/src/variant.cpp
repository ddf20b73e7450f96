#include "gimbalsim/dynamics/variant.hpp"

namespace gimbalsim {

std::string variantName(const Model& m) {
  std::string s = m.floating_base ? "floating" : "fixed";
  // Today's names for joint 1 ideal; a clearance joint 1 adds its kind.
  static const char* const kKind[] = {"ideal", "planar", "spatial"};
  if (m.joint1_kind != ClearanceKind::Ideal) s += std::string("_") + kKind[static_cast<int>(m.joint1_kind)] + "1";
  s += m.joint2_kind == ClearanceKind::Ideal   ? "_ideal"
       : m.joint2_kind == ClearanceKind::Planar ? "_clearance"
                                                : "_spatial";
  if (frictionActive(m)) s += "_friction";
  return s;
}

}  // namespace gimbalsim
