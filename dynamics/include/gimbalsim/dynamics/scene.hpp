// Scene files (YAML) -> validated Scene (Model + RunSpec), through the scene
// key table (key_registry.hpp). At the edge: parsing, validation and
// error messages live here, never in the step.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "gimbalsim/dynamics/key_registry.hpp"
#include "gimbalsim/dynamics/model.hpp"
#include "gimbalsim/dynamics/run_spec.hpp"

namespace gimbalsim {

/// Refusal of a scene: every problem found, each naming key and position.
class SceneError : public std::runtime_error {
 public:
  explicit SceneError(std::vector<Problem> problems);
  /// A refusal of the whole document (e.g. "<path>: cannot open scene file").
  explicit SceneError(const std::string& problem);
  /// Problems known only as their printed text (readers of other formats).
  explicit SceneError(const std::vector<std::string>& texts);
  /// The messages, as printed.
  const std::vector<std::string>& problems() const { return texts_; }
  /// The same with key and place as fields.
  const std::vector<Problem>& details() const { return details_; }

 private:
  std::vector<Problem> details_;
  std::vector<std::string> texts_;
};


/// Loads and validates a scene. `overrides` are "key=value" strings (from
/// --set), applied after the file. Throws SceneError.
Scene loadScene(const std::string& path, const std::vector<std::string>& overrides = {});

/// Same, from YAML text (`origin` names it in messages).
Scene loadSceneText(const std::string& yaml, const std::string& origin,
                          const std::vector<std::string>& overrides = {});

/// The scene keys (key_registry.hpp): what loadScene reads.
const KeyTable<Scene>& sceneTable();

/// Every scene key with type, unit, check, default and meaning (for
/// `gimbalsim keys` and the README).
std::vector<KeyInfo> sceneKeys();

}  // namespace gimbalsim
