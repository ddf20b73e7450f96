// Scene files (YAML) -> validated Scene (Model + RunSpec), through the scene
// key table (key_registry.hpp). At the edge: parsing, validation and
// error messages live here, never in the step.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "gimbalsim/input/input_error.hpp"
#include "gimbalsim/input/key_registry.hpp"
#include "gimbalsim/dynamics/model.hpp"
#include "gimbalsim/dynamics/run_spec.hpp"

namespace gimbalsim {

/// Refusal of a scene: every problem found, each naming key and position.
class SceneError : public InputError {
 public:
  using InputError::InputError;
};


/// Loads and validates a scene. `overrides` are "key=value" strings (from
/// --set), applied after the file. Throws SceneError.
Scene loadScene(const std::string& path, const std::vector<std::string>& overrides = {});

/// Same, from YAML text (`origin` names it in messages); the first `printed` overrides are a scene's printed
/// values (KeyTable::values), which a later override of an alternative key replaces.
Scene loadSceneText(const std::string& yaml, const std::string& origin,
                          const std::vector<std::string>& overrides = {}, std::size_t printed = 0);

/// The text of a scene file; throws SceneError "<path>: cannot open scene file: <why>".
std::string readSceneFile(const std::string& path);

/// After a table holding a Scene was loaded: the Model's derived terms, the
/// default name (origin), the warnings; SceneError when its first row is not
/// finite (a model the arithmetic cannot hold). Loaders of larger scenes (the
/// plant's, firmware_sim/plant_scene.hpp) call it as loadScene does.
void finishScene(Scene& sc, const std::string& origin, std::vector<std::string> warnings);

/// Why the shared contact.clearance = c [m] acts on no bearing of m ("" when
/// one joint with clearance runs at c): both joints ideal, or each bearing
/// set by its own jointN.contact.clearance. A study that labels its runs by
/// c refuses such a scene rather than record a clearance that never acted.
std::string sharedClearanceProblem(const Model& m, double c);

/// Why m cannot stand as a study's ideal run ("" when both joints are
/// ideal): the joints with clearance, by key. A study that labels a run
/// "ideal" refuses such a scene rather than compare the play against play.
std::string idealSceneProblem(const Model& m);

/// The scene keys (key_registry.hpp): what loadScene reads.
const KeyTable<Scene>& sceneTable();

/// Every scene key with type, unit, check, default and meaning (for
/// `gimbalsim keys` and the README).
std::vector<KeyInfo> sceneKeys();

}  // namespace gimbalsim
