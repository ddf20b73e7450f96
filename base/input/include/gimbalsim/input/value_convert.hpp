// Converters from a YAML value to a key's value; each throws ConvertError
// with the reason, which the loader places at the key.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "gimbalsim/input/value_format.hpp"

namespace YAML {
class Node;
}

namespace gimbalsim {

struct ConvertError {
  std::string msg;
};
double asNumber(const YAML::Node& n);  ///< finite
int asInt(const YAML::Node& n);        ///< whole, |x| <= 1e9
/// A list of N numbers; `expected` names the shape in the refusal ("expected <it>").
template <int N>
Eigen::Matrix<double, N, 1> asVector(const YAML::Node& n, const char* expected = nullptr);
/// [Ixx, Iyy, Izz], [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] or a 3x3 list of lists.
Mat3 asInertia(const YAML::Node& n);
std::string asString(const YAML::Node& n);
/// Index of the name given among `names`.
std::size_t asChoice(const YAML::Node& n, const std::vector<std::string>& names);

}  // namespace gimbalsim
