// What a document may hold and how files are read, for every reader of text
// input (the key tables and workprec's policy list alike).
#pragma once

#include <cstddef>
#include <string>

#include "gimbalsim/input/input_error.hpp"

namespace YAML {
class Node;
}

namespace gimbalsim {

/// What a document (file or --set value) may hold: checked on the parser's
/// events before yaml-cpp builds a tree, because yaml-cpp 0.7 aborts or
/// recurses without end on some inputs (a key that is not a scalar, an alias
/// to its own anchor) and expands nested aliases exponentially. The scene
/// files, controller configurations and profiles need none of what is refused.
struct InputBounds {
  static constexpr long long kMaxFileBytes = 1 << 20;     ///< a file larger than 1 MiB is refused unread
  static constexpr std::size_t kMaxSetBytes = 64 << 10;   ///< one --set argument: 64 KiB
  static constexpr std::size_t kMaxOverrides = 10000;     ///< --set arguments per run
  static constexpr int kMaxDepth = 16;                    ///< nested mappings and lists
  static constexpr long long kMaxNodes = 100000;          ///< keys, values and list items in a document
  static constexpr std::size_t kMaxScalarBytes = 4096;    ///< one key or value
  // Anchors (&a), aliases (*a) and more than one document are refused: no expansion to bound.
};

/// A YAML document that is not a key table (workprec's policy list) under the
/// same bounds and prescan as the tables; false and the refusal (its place) if not.
bool loadDocument(const std::string& text, const std::string& origin, YAML::Node& out, Problem& why);

/// The file's text; false (and why, naming the cause) if it is not a regular,
/// readable file of at most InputBounds::kMaxFileBytes. Never blocks on a FIFO
/// or reads a device.
bool readFile(const std::string& path, std::string& text, std::string* why = nullptr);

}  // namespace gimbalsim
