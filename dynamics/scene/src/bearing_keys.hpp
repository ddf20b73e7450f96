// The bearings' scene keys and checks (bearing_keys.cpp), for the scene
// table (scene.cpp). docs/scene_keys.md "The two bearings".
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "gimbalsim/input/key_registry.hpp"
#include "gimbalsim/dynamics/run_spec.hpp"

namespace gimbalsim::scene_keys {

/// The shared bearing keys, then joint 1's, then joint 2's.
std::vector<Key<Scene>> bearingKeys();
/// initial.ecc (both journals), initial.ecc1, initial.ecc2, initial.tilt1, initial.tilt2.
std::vector<Key<Scene>> journalKeys();
/// Old spellings: (alias, key).
std::vector<std::pair<std::string, std::string>> aliases();
/// Each bearing and journal checked against the bearing it acts on.
void validateBearings(const Scene& s, Given& g);
/// Each joint's bearing from the shared keys and its own (KeyTable::derive).
void deriveBearings(Scene& s, const Given& g);

}  // namespace gimbalsim::scene_keys
