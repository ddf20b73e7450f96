// The target profile's keys: a KeyTable segment (gimbalsim/dynamics/
// key_registry.hpp) that the controller configuration includes as profile.*,
// and that the plant side reads alone from the `profile:` section of such a
// file (firmware_sim --profile). Compiled into gimbalsim_scene (the YAML
// library); TargetProfile itself is in gimbalsim_pointing.
#pragma once

#include <string>

#include "gimbalsim/input/key_registry.hpp"
#include "gimbalsim/pointing/target_profile.hpp"

namespace gimbalsim::pointing {

/// The profile keys, without the "profile." prefix.
const KeyTable<TargetProfile>& profileKeys();

/// Reads only the `profile:` section of a controller configuration (keys
/// profile.*, defaults those of TargetProfile); other sections are not looked
/// at. Throws SceneError naming file:line:column and key.
TargetProfile loadTargetProfile(const std::string& path);
TargetProfile loadTargetProfileText(const std::string& yaml, const std::string& origin);

}  // namespace gimbalsim::pointing
