// Scene files (YAML) -> validated Model. At the edge: parsing, validation and
// error messages live here, never in the step.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "gimbalsim/dynamics/model.hpp"

namespace gimbalsim {

/// Refusal of a scene: every problem found, each naming key and position.
class SceneError : public std::runtime_error {
 public:
  explicit SceneError(std::vector<std::string> problems);
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  std::vector<std::string> problems_;
};

struct LoadedScene {
  Model model;
  std::vector<std::string> warnings;  ///< accepted but suspicious (e.g. triangle inequality)
};

/// Loads and validates a scene. `overrides` are "key=value" strings (from
/// --set), applied after the file. Throws SceneError.
LoadedScene loadScene(const std::string& path, const std::vector<std::string>& overrides = {});

/// Same, from YAML text (`origin` names it in messages).
LoadedScene loadSceneText(const std::string& yaml, const std::string& origin,
                          const std::vector<std::string>& overrides = {});

/// Every scene key with its type, unit and meaning (for `gimbalsim keys` and the README).
struct KeyInfo {
  std::string key, type, unit, help;
};
std::vector<KeyInfo> sceneKeys();

}  // namespace gimbalsim
