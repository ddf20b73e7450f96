// The plant's scene: the scene (Model + RunSpec, gimbalsim/scene) and the
// sensors the firmware reports through (sensors.* keys), from one scene file.
// firmware_sim, the in-process closed loop, the command line and the Python
// package load scenes this way; open-loop tools may load the Scene alone.
#pragma once

#include <string>
#include <vector>

#include "gimbalsim/firmware_sim/sensor_params.hpp"
#include "gimbalsim/scene/scene.hpp"

namespace gimbalsim::firmware {

struct PlantScene {
  Scene scene;
  SensorParams sensors;
};

/// Every key of a plant scene: the scene's, then sensors.*.
const KeyTable<PlantScene>& plantTable();

/// Loads and validates a plant scene; `overrides` are "key=value" (--set),
/// applied after the file. Throws SceneError naming key and place.
PlantScene loadPlantScene(const std::string& path, const std::vector<std::string>& overrides = {});

/// The overrides a closed loop's scene loads with: one that changes sim.step (to a positive number) takes
/// sim.output_interval = that step unless it gives one, as the Python sweeps do, and sim.duration = that step.
/// The loop reads neither (it records every period and runs the program's --duration); the scene's own
/// refused the new step (passes 113, 115), and a --set of them is refused as unread.
std::vector<std::string> closedLoopOverrides(std::vector<std::string> overrides);
/// Same, from YAML text (`origin` names it in messages); the first `printed` overrides are a scene's printed
/// values (loadSceneText).
PlantScene loadPlantSceneText(const std::string& yaml, const std::string& origin,
                              const std::vector<std::string>& overrides = {}, std::size_t printed = 0);

}  // namespace gimbalsim::firmware
