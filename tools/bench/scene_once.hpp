// A scene file loaded once per benchmark run: main's prepare loads every scene the filter selects (one that does
// not load refuses the run before any benchmark runs), and the benchmark takes that same object instead of
// reading and checking the file a second time.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "gimbalsim/firmware_sim/plant_scene.hpp"

namespace gimbalsim::bench {

/// loadPlantScene(path, overrides), read once per (path, overrides); what it throws reaches the caller.
inline const firmware::PlantScene& plantSceneOnce(const std::string& path, const std::vector<std::string>& overrides) {
  static std::map<std::pair<std::string, std::vector<std::string>>, firmware::PlantScene> loaded;  // nodes stay put
  auto key = std::make_pair(path, overrides);
  if (const auto it = loaded.find(key); it != loaded.end()) return it->second;
  return loaded.emplace(std::move(key), firmware::loadPlantScene(path, overrides)).first->second;
}

}  // namespace gimbalsim::bench
