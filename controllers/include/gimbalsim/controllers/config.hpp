// Controller configuration files (YAML): gains, limits, control period and the
// target profile in one file (controllers/config/default.yaml), with
// `--set key=value` overrides. At the edge: parsing and validation here, never
// in update(). The keys are a KeyTable (gimbalsim/input/key_registry.hpp),
// loaded like the scene keys: errors name the file, line and key.
#pragma once

#include <string>
#include <vector>

#include "gimbalsim/controllers/pid.hpp"
#include "gimbalsim/input/key_registry.hpp"
#include "gimbalsim/input/input_error.hpp"

namespace gimbalsim::controllers {

/// Refusal of a controller configuration: every problem, each naming key and place.
class ConfigError : public InputError {
 public:
  using InputError::InputError;
};

/// Loads and validates a controller configuration; `overrides` are "key=value"
/// (from --set), applied after the file. Every key is optional (defaults are
/// those of ControllerConfig). Throws ConfigError.
ControllerConfig loadControllerConfig(const std::string& path, const std::vector<std::string>& overrides = {});

/// Same, from YAML text (`origin` names it in messages).
ControllerConfig loadControllerConfigText(const std::string& yaml, const std::string& origin,
                                          const std::vector<std::string>& overrides = {});

/// Rebuilds c.plant_model from c.plant and c.gimbal (the loaders do; call it
/// after changing either in code).
void finalizePlant(ControllerConfig& c);

/// Every configuration key: control.*, profile.* (pointing::profileKeys(),
/// gimbalsim/pointing/profile_keys.hpp), azimuth.*, elevation.*.
const KeyTable<ControllerConfig>& controllerTable();

/// Every configuration key with type, unit, check, default and meaning
/// (`pointing_controller --keys`, docs/controller_keys.md).
std::vector<KeyInfo> controllerKeys();

/// Every key with its value in c, as "key=value" strings that
/// loadControllerConfig accepts as overrides (numbers in the fewest digits
/// that read back exactly, so loading them reproduces c).
std::vector<std::string> configValues(const ControllerConfig& c);

}  // namespace gimbalsim::controllers
