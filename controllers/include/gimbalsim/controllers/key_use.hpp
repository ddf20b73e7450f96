// Which controller keys a configuration reads: some are read only under the
// settings of others (pid.cpp, inertial_reference.cpp, model_feedforward.cpp,
// tracker_fusion.cpp). One table, for the study programs' refusals of a --set
// that would be recorded and never act, and for the Python sweeps' and
// tuners' (gimbalsim._idle_keys, through _controller_read_rules).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "gimbalsim/controllers/pid.hpp"

namespace gimbalsim::controllers {

/// A setting under which a key is read: the deciding key and the values that read it.
struct ReadingSetting {
  std::string key;
  std::vector<std::string> values;
};

/// A key (or a prefix ending in '.') and the conditions under which it is read: all must hold; a condition
/// holds when any one of its settings does.
struct KeyReadRule {
  std::string key;
  std::vector<std::vector<ReadingSetting>> conditions;
};

const std::vector<KeyReadRule>& controllerReadRules();

/// Why `key` is read by no run of configuration c ("" when it is read): the first condition of
/// controllerReadRules() that c does not meet; an antenna.* key is read only where the loop closes at the
/// antenna (a scene with an antenna sensor, and antenna.tracker use).
std::string controllerKeyIdle(const ControllerConfig& c, const std::string& key, bool scene_has_antenna_sensor);

/// Why c holds a value that runs as another one ("" when none does): pointing.accel_feedforward inertial
/// with pointing.mode joint runs as profile.
std::string controllerValueRunsAsAnother(const ControllerConfig& c);

/// The first of `overrides` ("key=value", given with `flag`) that c reads in no run, or "" when each is read:
/// by controllerKeyIdle, or named in `never_read` (key, why: what the caller's loop never reads); else, when c
/// holds a value that runs as another (controllerValueRunsAsAnother), the last override of its keys, or the
/// configuration itself when none is.
std::string idleControllerOverride(const char* flag, const std::vector<std::string>& overrides,
                                   const ControllerConfig& c, bool scene_has_antenna_sensor,
                                   const std::vector<std::pair<std::string, std::string>>& never_read);

}  // namespace gimbalsim::controllers
