// Where text enters the scene, configuration and profile readers, bounded
// (InputBounds, input_bounds.hpp): readFile() for files, loadBounded() for a
// document, which walks the parser's events before yaml-cpp builds a tree.
// Private to gimbalsim_input; given.cpp turns refusals into Problems.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

namespace gimbalsim {

/// A document refused before yaml-cpp built it: where, which key (dotted path
/// of the mapping keys above; "" at the top), why.
struct PrescanRefusal {
  YAML::Mark mark;
  std::string key;
  std::string msg;
};

/// The document parsed into a tree after the prescan passed. Throws
/// PrescanRefusal, YAML::Exception (syntax, with its mark) or std::exception.
YAML::Node loadBounded(const std::string& text);

}  // namespace gimbalsim
