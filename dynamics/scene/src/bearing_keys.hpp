// The bearings' and journals' scene keys and checks (bearing_keys.cpp,
// journal_keys.cpp), for the scene table (scene.cpp). docs/scene_keys.md
// "The two bearings".
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

// Shared by the two files.
/// The key that gave joint j's value of a bearing key (section "contact." or
/// "friction.", then the rest): its own if given, else the shared one.
std::string givenAs(const Given& g, int j, const std::string& section, const std::string& suffix);
/// Whether the scene gave joint key `key` itself (Scene::BothJoints::own_keys).
bool ownKeyGiven(const Scene& s, const std::string& key);
/// Each journal's initial eccentricity, then tilt, against its own bearing (journal_keys.cpp).
void checkInitialEcc(const Scene& s, Given& g);
void checkInitialTilt(const Scene& s, Given& g);
/// A --set friction key no bearing's law reads, said to act on nothing (friction_keys.cpp).
void idleFrictionKeys(const Scene& s, Given& g);
/// Each journal's eccentricity from initial.ecc unless its own key was given.
void deriveJournals(Scene& s, const Given& g);

}  // namespace gimbalsim::scene_keys
