// gimbalsim_controller_floor: is the controller's own pointing floor below
// the bearing's signature? The in-process closed loop (runClosedLoop, as
// gimbalsim_pointing_study) with PERFECT sensors (no encoder quantum, no
// noise, no gyro bias, no star tracker latency) on the ideal joint and at each
// elevation-joint clearance, one table: the truth pointing error's max and RMS
// while tracking and after the slew (hold + track; and when the after-slew max
// occurred), the joint tracking error
// and the attitude estimate's error (where a floor comes from), and the ratio
// ideal / first clearance. With --before-set the same runs of a second
// controller (the default + those overrides) come first: a before/after table.
// --markdown FILE writes the table as the body of docs/results/controller_floor.md
// (tools/pointing_study/run_controller_floor.sh adds the stamped header).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/controllers/pointing_controller.hpp"
#include "gimbalsim/firmware_sim/closed_loop.hpp"
#include "gimbalsim/controllers/key_use.hpp"
#include "gimbalsim/firmware_sim/study_idle.hpp"
#include "gimbalsim/input/key_registry.hpp"
#include "gimbalsim/io/output_file.hpp"
#include "gimbalsim/pointing/profile_windows.hpp"
#include "gimbalsim/program/program.hpp"
#include "gimbalsim/program/stop_signal.hpp"

#include "floor_table.hpp"

using namespace gimbalsim;
using namespace gimbalsim::controllers;
using namespace gimbalsim::floor_study;

namespace {

constexpr const char* kProgram = "gimbalsim_controller_floor";

int mainImpl(int argc, char** argv) {
  CLI::App app{"The controller's own pointing floor (ideal joint, perfect sensors) against the clearances'"};
  std::string ideal_path = "tools/scenes/paper_ideal.yaml", clearance_path = "tools/scenes/paper_clearance.yaml";
  std::string config_path, markdown_path;
  std::vector<std::string> sets, before_sets, scene_sets;
  std::vector<double> clearances{0.1e-3, 0.2e-3, 0.4e-3, 0.8e-3};
  double duration = 0.0;
  app.add_option("--ideal-scene", ideal_path, "scene with the ideal joint")->capture_default_str();
  app.add_option("--clearance-scene", clearance_path, "scene with the clearance joint")->capture_default_str();
  app.add_option("--config", config_path, "controller configuration file (default: the built-in defaults)");
  app.add_option("--set", sets, "controller override key=value (repeatable)");
  app.add_option("--before-set", before_sets,
                 "override of a second controller run first, the 'before' (repeatable; none: no before block)");
  app.add_option("--scene-set", scene_sets, "scene override key=value after the perfect sensors (repeatable)");
  app.add_option("--clearances", clearances, "radial clearances [m], comma-separated")->delimiter(',');
  app.add_option("--duration", duration, "simulated time [s] (default: the profile's track start + 5 s)");
  app.add_option("--markdown", markdown_path, "also write the tables as Markdown to this file");
  if (const auto rc = program::parse(app, argc, argv, kProgram)) return *rc;
  // Its own keys: a --scene-set of them was replaced by the program's value, silently (pass 64).
  if (const std::string why = program::overrideOfOwnKey(
          "--scene-set", scene_sets, {{"sim.duration", "--duration"}, {"contact.clearance", "--clearances"}});
      !why.empty()) {
    return program::refuse(kProgram, why);
  }
  // Keys the closed loop never reads: recorded with the runs, acting on none (pass 66: torque.tau1=1000 ran as 0).
  if (const std::string why = firmware::idleSceneOverride("--scene-set", scene_sets); !why.empty()) {
    return program::refuse(kProgram, why);
  }
  if (app.count("--duration") && !(duration > 0.0 && std::isfinite(duration))) {
    return program::refuse(kProgram, "--duration: must be a positive number of seconds");
  }
  for (double c : clearances) {
    if (!(c > 0.0 && std::isfinite(c))) return program::refuse(kProgram, "--clearances: each must be > 0 [m]");
  }
  if (const std::string why = program::repeatedValue("--clearances", clearances); !why.empty()) {
    return program::refuse(kProgram, why);
  }
  auto load = [&](const std::vector<std::string>& extra) {
    std::vector<std::string> all = sets;
    all.insert(all.end(), extra.begin(), extra.end());
    return config_path.empty() ? loadControllerConfigText("", "the built-in default configuration", all)
                               : loadControllerConfig(config_path, all);
  };
  // Perfect sensors: the truth the controller sees, only the 1 kHz sampling left.
  std::vector<std::string> perfect{"sensors.encoder_resolution=0", "sensors.encoder_noise=0", "sensors.rate_noise=0",
                                   "sensors.gyro_noise=0",         "sensors.gyro_bias=[0,0,0]", "sensors.gyro_bias_walk=0",
                                   "sensors.star_tracker_noise=0", "sensors.star_tracker_latency=0"};
  perfect.insert(perfect.end(), scene_sets.begin(), scene_sets.end());
  // A refusal names what the user gave: --set #k, --before-set #k, --scene-set #k, --clearances.
  const auto numbered = [](const std::string& flag, const std::vector<std::string>& given) {
    std::vector<std::string> labels;
    for (std::size_t k = 0; k < given.size(); ++k) labels.push_back(flag + " #" + std::to_string(k + 1) + " '" + given[k] + "'");
    return labels;
  };
  std::vector<std::string> scene_labels(perfect.size() - scene_sets.size(), std::string(kProgram) + "'s perfect sensors");
  for (const std::string& l : numbered("--scene-set", scene_sets)) scene_labels.push_back(l);
  const auto refused = [](const InputError& e, const std::vector<std::string>& labels) {
    return program::refuse(kProgram, InputError(relabelledProblems(e, labels)));
  };
  std::vector<std::pair<std::string, ControllerConfig>> controllers;
  std::vector<std::pair<std::string, firmware::PlantScene>> scenes;
  std::vector<std::string> controller_labels = numbered("--set", sets);
  try {
    if (!before_sets.empty()) {
      std::vector<std::string> labels = controller_labels;
      for (const std::string& l : numbered("--before-set", before_sets)) labels.push_back(l);
      try {
        controllers.emplace_back("before", load(before_sets));
      } catch (const InputError& e) {
        return refused(e, labels);
      }
    }
    controllers.emplace_back("after", load({}));
  } catch (const InputError& e) {
    return refused(e, controller_labels);
  }
  try {
    scenes.emplace_back("ideal", firmware::loadPlantScene(ideal_path, firmware::closedLoopOverrides(perfect)));
  } catch (const InputError& e) {
    return refused(e, scene_labels);
  }
  if (const std::string why = idealSceneProblem(scenes.back().second.scene.model); !why.empty()) {
    return program::refuse(kProgram, "--ideal-scene " + ideal_path + ": " + why);
  }
  for (double c : clearances) {
    std::vector<std::string> s = perfect;
    char label[32];
    std::snprintf(label, sizeof label, "c=%gmm", c * 1e3);
    s.push_back("contact.clearance=" + formatNumber(c));
    std::vector<std::string> labels = scene_labels;
    labels.push_back("--clearances " + formatNumber(c));
    try {
      scenes.emplace_back(label, firmware::loadPlantScene(clearance_path, firmware::closedLoopOverrides(s)));
    } catch (const InputError& e) {
      return refused(e, labels);
    }
    if (const std::string why = sharedClearanceProblem(scenes.back().second.scene.model, c); !why.empty()) {
      return program::refuse(kProgram, "--clearance-scene " + clearance_path + ": --clearances " + formatNumber(c) +
                                           " [m] would never act: " + why);
    }
  }
  const auto stem = [](const std::string& path) { return std::filesystem::path(path).stem().string(); };
  const ControllerConfig& main_cfg = controllers.back().second;
  for (const auto& [label, ps] : scenes) {  // refused before any run: a period the plant cannot tick at
    for (const auto& [name, c] : controllers) {
      if (const std::string why = firmware::controlPeriodProblem(ps, c.period); !why.empty()) {
        return program::refuse(kProgram, "--set " + why + " (run " + label + ", controller " + name + ")");
      }
    }
  }
  // A --set no controller reads (or a --before-set the "before" one does not) would be recorded as in effect
  // and act on nothing (pass 80).
  const bool any_antenna_sensor =
      std::any_of(scenes.begin(), scenes.end(), [](const auto& s) { return s.second.sensors.antenna_sensors; });
  const auto idle = [&](const char* flag, const std::vector<std::string>& given, const ControllerConfig& c) {
    return idleControllerOverride(flag, given, c, any_antenna_sensor, firmware::closedLoopIdleControllerKeys());
  };
  std::string why_set;  // a --set is in both controllers: refused when neither reads it
  for (const auto& [name, c] : controllers) {
    why_set = idle("--set", sets, c);
    if (why_set.empty()) break;
  }
  if (!why_set.empty()) return program::refuse(kProgram, why_set);
  if (const std::string why = idle("--before-set", before_sets, controllers.front().second); !why.empty()) {
    return program::refuse(kProgram, why);
  }
  // A seed with no noise to draw: recorded with the runs, acting on none.
  const bool any_noise =
      std::any_of(scenes.begin(), scenes.end(), [](const auto& s) { return s.second.sensors.anyNoise(); });
  if (const std::string why = firmware::idleSeedOverride("--scene-set", scene_sets, any_noise); !why.empty()) {
    return program::refuse(kProgram, why);
  }
  const double T = duration > 0.0 ? duration : main_cfg.profile.trackStart() + 5.0;
  if (const std::string why = wholeMultipleProblem(T, main_cfg.period, "the control period (control.period)");
      !why.empty()) {
    return program::refuse(kProgram, "--duration: " + why);
  }
  // Every figure of the table lies after the slew: a run that ends before is refused, not run.
  if (const std::string why = afterSlewNotReached(main_cfg.profile.slewEnd(), T); !why.empty()) {
    return program::refuse(kProgram, "--duration: " + why + " (every figure of the table lies after the slew)");
  }
  // A --scene-set the scenes' joints leave idle: refused where it acts in no run, said where in some (pass 72).
  const int first_scene_set = static_cast<int>(perfect.size() - scene_sets.size()) + 1;
  std::vector<firmware::StudyScene> study_scenes;
  // ... and a sensor key they leave idle (the antenna's where no controller closes there, a sample's under an
  // outage over the whole run)
  const bool antenna_loop =
      std::any_of(controllers.begin(), controllers.end(), [](const auto& c) { return c.second.antenna.use_tracker; });
  // the star tracker's samples are judged at the controllers' one period (not at all when they differ)
  const bool one_period = std::all_of(controllers.begin(), controllers.end(),
                                      [&](const auto& c) { return c.second.period == main_cfg.period; });
  for (const auto& [label, ps] : scenes) {
    const firmware::SensorRun run{T, one_period ? main_cfg.period : 0.0, antenna_loop, ps.scene.model.floating_base,
                                  nullptr};
    study_scenes.push_back({label == "ideal" ? stem(ideal_path) : stem(clearance_path), &ps.scene, first_scene_set,
                            &ps.sensors, run, ""});
  }
  std::vector<std::string> partly_idle;
  if (const std::string why = firmware::idleInEveryRun("--scene-set", scene_sets, study_scenes, &partly_idle);
      !why.empty()) {
    return program::refuse(kProgram, why);
  }
  for (const std::string& w : partly_idle) std::fprintf(stderr, "%s: warning: %s\n", kProgram, w.c_str());
  std::optional<io::OutputFile> md_out;
  if (!markdown_path.empty()) {
    std::vector<std::string> inputs{ideal_path, clearance_path};
    if (!config_path.empty()) inputs.push_back(config_path);
    try {  // a path no output may take (a link, a folder, an input, no such folder): refused (2)
      io::checkOutputPaths({markdown_path}, inputs);
    } catch (const io::OutputError& e) {
      return program::refuse(kProgram, std::string("--markdown: ") + e.what());
    }
    try {  // a folder that takes no file (read-only, full): could not be written (4)
      md_out.emplace(markdown_path, inputs);
    } catch (const io::OutputError& e) {
      return program::unwritable(kProgram, std::string("--markdown: ") + e.what());
    }
  }
  // A --scene-set of a sensor key runs other sensors than perfect ones: said wherever the runs are described.
  std::string overridden;
  for (const std::string& kv : scene_sets) {
    if (kv.rfind("sensors.", 0) == 0) overridden += (overridden.empty() ? "" : ", ") + kv;
  }
  const std::string sensors = overridden.empty() ? "perfect sensors" : "perfect sensors except " + overridden;
  std::printf("# %g s per run, tracking from %g s, slew ends at %g s; %s; truth pointing error\n", T,
              main_cfg.profile.trackStart(), main_cfg.profile.slewEnd(), sensors.c_str());
  // The scenes as run, by their files' names (it named paper_ideal and paper_clearance whatever ran).
  std::string md = "`build/bin/gimbalsim_controller_floor` (tools/pointing_study/floor_main.cpp): the in-process "
                   "closed loop with " + sensors + " on `" + stem(ideal_path) + "` and on `" + stem(clearance_path) +
                   "` at each clearance, " + formatSignificant(T, 6) + " s per run (slew ends at " +
                   formatSignificant(main_cfg.profile.slewEnd(), 6) + " s, tracking from " +
                   formatSignificant(main_cfg.profile.trackStart(), 6) +
                   " s); the truth pointing error (boresight against the target's line of sight). \"After the slew\" "
                   "is [" + formatSignificant(main_cfg.profile.slewEnd(), 6) + ", " + formatSignificant(T, 6) +
                   "] s: the hold, with the settling from the slew's end, and the track; \"at\" is the time of its "
                   "max. Goal: the ideal joint's figures at most 1/5 of the first clearance's.\n\n";
  bool all_ok = true;
  io::installStopHandlers();
  for (const auto& [name, cfg] : controllers) {
    std::vector<Row> rows;
    for (const auto& [label, ps] : scenes) {
      rows.push_back(runOne(ps, cfg, T, label));
      // The table compares every run with the ideal one: a part of it answers nothing, so nothing is written.
      if (io::stopRequested()) {
        std::fprintf(stderr, "%s: interrupted by %s: nothing written\n", kProgram, io::stopSignalName());
        return io::stopExitCode();
      }
      all_ok = all_ok && rows.back().ok;
    }
    std::string overrides;
    for (const std::string& kv : before_sets) overrides += (overrides.empty() ? "" : ", ") + kv;
    const std::string title = name == "before" ? "before (the default with " + overrides + ")" : "after (the default)";
    std::fputs(table(title, rows, false).c_str(), stdout);
    std::fflush(stdout);
    md += table(title, rows, true);
  }
  if (md_out) {
    std::fputs(md.c_str(), md_out->stream());
    if (!md_out->commit()) {
      std::fprintf(stderr, "%s: --markdown: %s\n", kProgram, md_out->error().c_str());
      return program::kOutput;
    }
  }
  return all_ok ? program::kOk : program::kStopped;
}

}  // namespace

int main(int argc, char** argv) {
  return program::guardedMain(kProgram, [&] { return mainImpl(argc, argv); });
}
