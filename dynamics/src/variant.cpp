#include "gimbalsim/dynamics/variant.hpp"

namespace gimbalsim {

std::string variantName(const Model& m) {
  std::string s = m.floating_base ? "floating" : "fixed";
  s += m.clearance_joint ? "_clearance" : "_ideal";
  if (frictionActive(m)) s += "_friction";
  return s;
}

}  // namespace gimbalsim
