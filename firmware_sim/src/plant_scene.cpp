#include <cstdlib>
#include <cmath>

#include "gimbalsim/firmware_sim/plant_scene.hpp"

namespace gimbalsim::firmware {

const KeyTable<PlantScene>& plantTable() {
  static const KeyTable<PlantScene> table = [] {
    KeyTable<PlantScene> t;
    t.words = sceneTable().words;
    embed(t.keys, "", sceneTable().keys, [](auto& p) -> auto& { return p.scene; });
    embed(t.keys, "sensors.", sensorKeys(), [](auto& p) -> auto& { return p.sensors; });
    t.derive = [](PlantScene& p, const Given& g) { sceneTable().derive(p.scene, g); };
    t.aliases = sceneTable().aliases;
    t.validate = [](const PlantScene& p, Given& g) {
      sceneTable().validate(p.scene, g);
      validateSensors(p.sensors, g, "sensors.");
    };
    return t;
  }();
  return table;
}

PlantScene loadPlantSceneText(const std::string& yaml, const std::string& origin,
                              const std::vector<std::string>& overrides, std::size_t printed) {
  std::vector<std::string> warnings;
  std::vector<std::pair<int, std::string>> idle_sets;
  PlantScene out = loadKeys<SceneError>(plantTable(), yaml, origin, overrides, &warnings, printed, &idle_sets);
  out.scene.idle_sets = std::move(idle_sets);
  finishScene(out.scene, origin, std::move(warnings));
  return out;
}

PlantScene loadPlantScene(const std::string& path, const std::vector<std::string>& overrides) {
  return loadPlantSceneText(readSceneFile(path), path, overrides);
}

std::vector<std::string> closedLoopOverrides(std::vector<std::string> overrides) {
  std::string step;
  bool interval = false, duration = false;
  for (const std::string& kv : overrides) {
    interval = interval || kv.rfind("sim.output_interval=", 0) == 0;
    duration = duration || kv.rfind("sim.duration=", 0) == 0;
    if (kv.rfind("sim.step=", 0) == 0) step = kv.substr(9);
  }
  char* end = nullptr;
  const double h = step.empty() ? 0.0 : std::strtod(step.c_str(), &end);
  if (step.empty() || end == nullptr || *end != '\0' || !std::isfinite(h) || !(h > 0.0)) return overrides;
  if (!interval) overrides.push_back("sim.output_interval=" + step);
  // The program's own length (--duration) runs; the scene's is never read, and one step always divides it.
  if (!duration) overrides.push_back("sim.duration=" + step);
  return overrides;
}

}  // namespace gimbalsim::firmware
