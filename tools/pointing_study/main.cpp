// gimbalsim_pointing_study: the paper's question (how much does the radial
// clearance of a bearing cost in pointing?) answered in closed loop.
// One in-process closed-loop run (study_run.hpp, runClosedLoop: firmware model + pointing
// controller, the same truth as the LCM bench in lockstep) on the ideal joint
// and one per clearance scene and clearance, all with the same controller
// configuration, profile and duration. Writes, in --out:
//   pointing_error.csv  t and the truth pointing error of every run, one column each
//   summary.csv         one row per run: peak / RMS while tracking, peak over the run, plant status
//   config.txt          the controller configuration in effect (key=value)
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cerrno>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "gimbalsim/scene/scene.hpp"
#include "gimbalsim/firmware_sim/closed_loop.hpp"
#include "gimbalsim/controllers/key_use.hpp"
#include "gimbalsim/firmware_sim/study_idle.hpp"
#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/input/key_registry.hpp"
#include "gimbalsim/io/output_file.hpp"
#include "gimbalsim/pointing/profile_windows.hpp"
#include "gimbalsim/program/program.hpp"
#include "gimbalsim/program/stop_signal.hpp"
#include "study_run.hpp"

using namespace gimbalsim;
using namespace gimbalsim::controllers;
using gimbalsim::pointing_study::Study;

namespace {

// Exit codes: the project's table (docs/usage.md "Exit codes", mirrored in program.hpp); refusals
// (bad argument, scene or configuration) leave through program::kRefused.
constexpr int kExitWrite = program::kOutput;     // an output file could not be written
constexpr int kExitStopped = program::kStopped;  // a plant stopped (results still written)

/// The realistic sensors: the pointing budget's upper bounds
/// (tools/sweeps/pointing_budget.yaml), star tracker noise 2e-5 rad per axis,
/// gyro bias 1e-5 rad/s (equal parts on the three base axes). "Perfect" is
/// the scene's own: no noise in the shipped scenes, encoders quantised.
const std::vector<std::string> kRealisticSensors{"sensors.star_tracker_noise=2e-5",
                                                 "sensors.gyro_bias=[5.7735e-6, 5.7735e-6, 5.7735e-6]"};

/// The tracker case: the perfect sensors plus the antenna's own (noise 0,
/// tools/scenes/paper_spatial2_tracker.yaml's), which the default controller
/// closes its loop on (docs/MODEL.md 11.7).
const std::vector<std::string> kTrackerSensors{"sensors.antenna=tracker_gyro", "sensors.tracker_noise=0",
                                               "sensors.tracker_bias=[0, 0]", "sensors.antenna_gyro_noise=0",
                                               "sensors.antenna_gyro_bias=[0, 0, 0]"};

std::string clearanceLabel(double c) {
  char b[40];
  std::snprintf(b, sizeof b, "c=%gmm", c * 1e3);
  return b;
}

int refuse(const std::string& option, const std::string& why) {
  return program::refuse("gimbalsim_pointing_study", option + ": " + why);
}

int mainImpl(int argc, char** argv) {
  CLI::App app{"Closed-loop truth pointing error on the ideal joint and against bearing clearance"};
  // Defaults relative to the working directory (the repository root), never a source path baked in.
  std::string ideal_path = "tools/scenes/paper_ideal.yaml";
  std::vector<std::string> clearance_paths{"tools/scenes/paper_clearance.yaml"};
  std::string config_path;  // "": the built-in default controller (= controllers/config/default.yaml)
  std::string out_dir = "out/pointing_study";
  std::vector<std::string> scene_sets, sets;
  std::vector<double> clearances{0.1e-3, 0.25e-3, 0.5e-3, 0.8e-3};
  double duration = 0.0;
  bool quick = false;
  std::string sensors = "perfect";
  app.add_option("--ideal-scene", ideal_path, "scene with the ideal joint")->capture_default_str();
  app.add_option("--clearance-scene", clearance_paths,
                 "scene with clearance, each run at every clearance (repeatable; joint kinds: structure.joint1/joint2)")
      ->capture_default_str();
  app.add_option("--config", config_path, "controller configuration file (default: the built-in defaults)");
  app.add_option("--set", sets, "controller override key=value (repeatable)");
  app.add_option("--scene-set", scene_sets, "scene override key=value for every run (repeatable)");
  app.add_option("--clearances", clearances, "radial clearances [m] (contact.clearance), comma-separated")
      ->delimiter(',');
  app.add_option("--duration", duration, "simulated time [s], whole control periods, at most 1e9 of them (default: the profile's track start + 5 s)");
  app.add_option("--out", out_dir, "output directory");
  app.add_option("--sensors", sensors,
                 "perfect (the scene's), realistic (star tracker 2e-5 rad, gyro bias 1e-5 rad/s), tracker (perfect "
                 "with the antenna's tracker and gyro, noise 0), both (perfect and realistic) or all three")
      ->check(CLI::IsMember({"perfect", "realistic", "tracker", "both", "all"}))
      ->capture_default_str();
  app.add_flag("--quick", quick, "smoke run: track start + 0.5 s, clearances 0.25 and 0.5 mm (unless given)");
  if (const auto rc = program::parse(app, argc, argv, "gimbalsim_pointing_study")) return *rc;
  // Its own keys: a --scene-set of them was replaced by the study's value, silently (pass 64).
  if (const std::string why = program::overrideOfOwnKey(
          "--scene-set", scene_sets, {{"sim.duration", "--duration"}, {"contact.clearance", "--clearances"}});
      !why.empty()) {
    return program::refuse("gimbalsim_pointing_study", why);
  }
  // Keys the closed loop never reads: recorded with the runs, acting on none (pass 66: torque.tau1=1000 ran as 0).
  if (const std::string why = firmware::idleSceneOverride("--scene-set", scene_sets); !why.empty()) {
    return program::refuse("gimbalsim_pointing_study", why);
  }
  if (app.count("--duration") && !(duration > 0.0 && std::isfinite(duration))) {
    return refuse("--duration", "must be a positive number of seconds, got " + formatNumber(duration));
  }
  if (quick && !app.count("--clearances")) clearances = {0.25e-3, 0.5e-3};
  for (double c : clearances) {
    if (!(c > 0.0 && std::isfinite(c))) return refuse("--clearances", "each must be > 0 [m], got " + formatNumber(c));
  }
  if (out_dir.empty()) return refuse("--out", "empty directory name");
  // The default folder is made only after every check (below): a refused run leaves nothing.
  if (app.count("--out")) {
    if (const std::string why = gimbalsim::io::outputFolderProblem(out_dir, true); !why.empty()) {
      return refuse("--out", "'" + out_dir + "': " + why);
    }
  }

  ControllerConfig cfg;
  struct Planned {
    firmware::PlantScene scene;
    double clearance = 0.0;  ///< [m], 0 for the ideal joint
    std::string scene_name, label, sensors;
    int first_scene_set = 1;  ///< the loader's number of --scene-set #1 among this run's overrides
  };
  // A scene is named by its file's stem, as gimbalsim_controller_floor names it: a modified copy keeps the
  // shipped scene's `name:` and would read as the shipped scene (pass 55).
  const auto stem = [](const std::string& path) { return std::filesystem::path(path).stem().string(); };
  for (std::size_t i = 0; i < clearance_paths.size(); ++i) {
    // The stem names runs and pointing_error.csv's columns: a comma, quote or newline would shift or split
    // them (pass 56), so a name is letters, digits and . _ - + only.
    const std::string name = stem(clearance_paths[i]);
    const auto bad = std::find_if(name.begin(), name.end(), [](unsigned char ch) {
      return !(std::isalnum(ch) || ch == '.' || ch == '_' || ch == '-' || ch == '+');
    });
    if (name.empty() || bad != name.end()) {
      return refuse("--clearance-scene", "'" + clearance_paths[i] + "': its file name names the runs and the "
                    "columns of pointing_error.csv, so it may hold only letters, digits and . _ - +; rename it");
    }
    for (std::size_t j = 0; j < i; ++j) {
      // One file under two names (a link) is the same scene given twice: it ran twice (pass 56).
      std::error_code ec;
      const bool same = clearance_paths[i] == clearance_paths[j] ||
                        std::filesystem::equivalent(clearance_paths[i], clearance_paths[j], ec);
      if (!same && stem(clearance_paths[i]) != stem(clearance_paths[j])) continue;
      const std::string both = "'" + clearance_paths[j] + "' and '" + clearance_paths[i] + "'";
      return refuse("--clearance-scene",
                    !same                                      ? both + " have the same file name, which names their "
                                                                        "runs; rename one"
                    : clearance_paths[i] == clearance_paths[j] ? "'" + clearance_paths[i] + "' given twice"
                                                               : both + " are one file: the same scene given twice");
    }
  }
  std::vector<Planned> scenes;
  try {
    cfg = config_path.empty() ? loadControllerConfigText("", "the built-in default configuration", sets)
                              : loadControllerConfig(config_path, sets);
  } catch (const InputError& e) {
    std::string why;
    for (const auto& p : e.problems()) why += "\n  " + p;
    return refuse("--config/--set", "configuration refused:" + why);
  }
  std::vector<std::string> cases{"perfect", "realistic"};
  if (sensors == "all") cases.push_back("tracker");
  else if (sensors != "both") cases = {sensors};
  // Overrides named as the user gave them: --sensors, --scene-set #k, or --clearances (not "--set #k").
  std::vector<std::string> labels;
  try {
    for (const std::string& sensor_case : cases) {
      std::vector<std::string> base;
      labels.clear();
      if (sensor_case == "realistic") {
        base = kRealisticSensors;
        for (const std::string& kv : base) labels.push_back("--sensors realistic '" + kv + "'");
      } else if (sensor_case == "tracker") {
        base = kTrackerSensors;
        for (const std::string& kv : base) labels.push_back("--sensors tracker '" + kv + "'");
      }
      const std::size_t case_keys = base.size();  // the case's own; a key two --scene-set give takes the later
      for (std::size_t k = 0; k < scene_sets.size(); ++k) {
        // A case's own key set again would relabel the runs: sensors=tracker with the tracker switched off.
        const std::string key = scene_sets[k].substr(0, scene_sets[k].find('='));
        for (std::size_t b = 0; b < case_keys; ++b) {  // (pass 88: not the --scene-set before it)
          if (base[b].substr(0, base[b].find('=')) == key) {
            return refuse("--scene-set", "#" + std::to_string(k + 1) + " '" + scene_sets[k] + "' sets " + key +
                                             ", which " + labels[b] + " sets: the runs would be labelled '" +
                                             sensor_case + "' without its sensors; leave " + key + " to --sensors");
          }
        }
        base.push_back(scene_sets[k]);
        labels.push_back("--scene-set #" + std::to_string(k + 1) + " '" + scene_sets[k] + "'");
      }
      const std::string suffix = cases.size() > 1 ? "_" + sensor_case : "";
      const int first_scene_set = static_cast<int>(base.size() - scene_sets.size()) + 1;
      scenes.push_back({firmware::loadPlantScene(ideal_path, firmware::closedLoopOverrides(base)), 0.0,
                        stem(ideal_path), "ideal" + suffix, sensor_case, first_scene_set});  // sensor keys: below
      if (const std::string why = idealSceneProblem(scenes.back().scene.scene.model); !why.empty()) {
        return refuse("--ideal-scene", ideal_path + ": " + why);
      }
      for (const std::string& path : clearance_paths) {
        for (double c : clearances) {
          std::vector<std::string> s = base;
          s.push_back("contact.clearance=" + formatNumber(c));
          labels.resize(base.size());
          labels.push_back("--clearances " + formatNumber(c) + " [m]");
          firmware::PlantScene ps = firmware::loadPlantScene(path, firmware::closedLoopOverrides(s));
          if (const std::string why = sharedClearanceProblem(ps.scene.model, c); !why.empty()) {
            return refuse("--clearance-scene/--clearances",
                          path + ": --clearances " + formatNumber(c) + " [m] would never act: " + why);
          }
          // One clearance scene keeps the short labels; several are told apart by scene name.
          std::string label = clearanceLabel(c);
          if (clearance_paths.size() > 1) label = stem(path) + "_" + label;
          scenes.push_back({std::move(ps), c, stem(path), label + suffix, sensor_case, first_scene_set});
        }
      }
    }
  } catch (const InputError& e) {
    std::string why;
    for (const auto& p : relabelledProblems(e, labels)) why += "\n  " + p;
    return refuse("--ideal-scene/--clearance-scene/--scene-set/--clearances/--sensors", "scene refused:" + why);
  }

  for (std::size_t i = 0; i < scenes.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (scenes[i].label == scenes[j].label) {
        return refuse("--clearance-scene/--clearances", "two runs would both be '" + scenes[i].label +
                                                            "' (a clearance given twice, or two its six significant digits do not tell apart)");
      }
    }
  }

  for (const auto& sc : scenes) {  // refused before any run: a period the plant cannot tick at
    if (const std::string why = firmware::controlPeriodProblem(sc.scene, cfg.period); !why.empty()) {
      return refuse("--config/--set", why + " (run " + sc.label + ")");
    }
  }
  // A --set the loop never reads would be recorded in config.txt as in effect (pass 80).
  const bool any_antenna_sensor =
      std::any_of(scenes.begin(), scenes.end(), [](const Planned& p) { return p.scene.sensors.antenna_sensors; });
  if (const std::string why = idleControllerOverride("--set", sets, cfg, any_antenna_sensor,
                                                     firmware::closedLoopIdleControllerKeys());
      !why.empty()) {
    return program::refuse("gimbalsim_pointing_study", why);
  }
  // A seed with no noise to draw: recorded with the runs, acting on none.
  const bool any_noise =
      std::any_of(scenes.begin(), scenes.end(), [](const Planned& p) { return p.scene.sensors.anyNoise(); });
  if (const std::string why = firmware::idleSeedOverride("--scene-set", scene_sets, any_noise); !why.empty()) {
    return program::refuse("gimbalsim_pointing_study", why);
  }
  firmware::ClosedLoopOptions opt;
  const double track_start = cfg.profile.trackStart();
  opt.duration = duration > 0.0 ? duration : track_start + (quick ? 0.5 : 5.0);
  // Its bound first (the whole-multiple check below has a looser one of its own), before any folder is made.
  if (!(opt.duration / cfg.period <= 1e9)) {
    return refuse("--duration", "gives more than 1e9 control periods of " + formatNumber(cfg.period) + " s");
  }
  // The loop runs whole control periods: a duration between two is refused, not rounded.
  if (const std::string why = wholeMultipleProblem(opt.duration, cfg.period, "the control period (control.period)");
      !why.empty()) {
    return refuse("--duration", why);
  }
  // A --scene-set the scenes' joints leave idle (joint 1's friction on an ideal joint 1): refused where it acts in
  // no run, said where it acts in some (pass 72).
  std::vector<firmware::StudyScene> study_scenes;
  // ... and a sensor key its runs leave idle (the antenna's without one, a sample's under a whole-run outage)
  for (const Planned& p : scenes) {
    const firmware::SensorRun run{opt.duration, cfg.period, cfg.antenna.use_tracker,
                                  p.scene.scene.model.floating_base, nullptr};
    study_scenes.push_back({p.scene_name, &p.scene.scene, p.first_scene_set, &p.scene.sensors, run,
                            cases.size() > 1 ? p.sensors : ""});
    // (pass 101) a --scene-set leaving the realistic case's own keys acting on nothing (its star tracker noise
    // under a latency that lets no sample act) ran labelled 'realistic' without its sensors; (pass 103) the tracker
    // case's under a tracker outage over every sample, labelled 'tracker' (its loop on the antenna: judged so)
    const bool tracker = p.sensors == "tracker";
    const std::vector<std::string> none;
    firmware::SensorRun own_run = run;
    own_run.antenna_loop = own_run.antenna_loop || tracker;
    for (const std::string& kv : p.sensors == "realistic" ? kRealisticSensors : tracker ? kTrackerSensors : none) {
      const std::string key = kv.substr(0, kv.find('='));
      if (const std::string why = firmware::sensorKeyIdle(key, p.scene.sensors, own_run); !why.empty()) {
        return refuse("--scene-set", "leaves --sensors " + p.sensors + "'s " + key + " acting on nothing in the runs "
                                         "of '" + p.scene_name + "' (" + why + "): they would be labelled '" +
                                         p.sensors + "' without its sensors");
      }
    }
  }
  // A --scene-set of a sensor key is said with the case, as gimbalsim_controller_floor says it (the runs were
  // labelled "perfect" over noisy sensors, pass 56), where it acts: a key idle in a case's runs is not said
  // with them (pass 91: the perfect runs of --sensors both on a fixed base, "perfect except star_tracker_rate")
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    Planned& p = scenes[i];
    const std::string sensor_case = p.sensors;
    for (const std::string& kv : scene_sets) {
      const std::string key = kv.substr(0, kv.find('='));
      if (key.rfind("sensors.", 0) != 0) continue;
      if (!firmware::sensorKeyIdle(key, p.scene.sensors, study_scenes[i].run).empty()) continue;
      p.sensors += (p.sensors == sensor_case ? " except " : " and ") + kv;
    }
  }
  std::vector<std::string> partly_idle;
  if (const std::string why = firmware::idleInEveryRun("--scene-set", scene_sets, study_scenes, &partly_idle);
      !why.empty()) {
    return program::refuse("gimbalsim_pointing_study", why);
  }
  for (const std::string& w : partly_idle) std::fprintf(stderr, "gimbalsim_pointing_study: warning: %s\n", w.c_str());
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) {
    std::fprintf(stderr, "gimbalsim_pointing_study: cannot create %s: %s\n", out_dir.c_str(),
                 ec.message().c_str());
    return kExitWrite;
  }
  // (pass 45) two studies into one --out each wrote the folder's files: the second is refused
  if (const std::string why = gimbalsim::io::holdOutputFolder(out_dir); !why.empty()) return refuse("--out", why);
  const std::filesystem::path dir(out_dir);
  try {
    std::vector<std::string> inputs{ideal_path};
    inputs.insert(inputs.end(), clearance_paths.begin(), clearance_paths.end());
    if (!config_path.empty()) inputs.push_back(config_path);
    gimbalsim::io::checkOutputPaths(
        {(dir / "config.txt").string(), (dir / "pointing_error.csv").string(), (dir / "summary.csv").string()},
        inputs);
  } catch (const gimbalsim::io::OutputError& e) {
    return refuse("--out", e.what());
  }
  // The three files' temporaries exist before the first run: a folder that takes no file costs no run.
  std::vector<std::unique_ptr<gimbalsim::io::OutputFile>> files;
  try {
    for (const char* name : {"config.txt", "pointing_error.csv", "summary.csv"}) {
      files.push_back(std::make_unique<gimbalsim::io::OutputFile>((dir / name).string()));
    }
  } catch (const gimbalsim::io::OutputError& e) {
    return program::unwritable("gimbalsim_pointing_study", std::string("--out: ") + e.what());
  }

  std::string config_text, mode = "joint-space (no pointing.mode key)";
  for (const std::string& kv : configValues(cfg)) {
    config_text += kv + "\n";
    if (kv.rfind("pointing.mode=", 0) == 0) mode = kv.substr(14);
  }
  std::printf("# %g s per run (tracking from %g s), control period %g s, controller mode: %s\n", opt.duration,
              track_start, cfg.period, mode.c_str());
  std::printf("%-34s %-18s %11s %13s %13s %13s  %s\n", "run", "scene", "clearance[m]", "peak_trk[rad]",
              "rms_trk[rad]", "peak_run[rad]", "status");

  std::vector<Study> runs;
  // SIGINT/SIGTERM: the run in progress stops within kStopCheckTicks ticks and is dropped; the CSVs hold
  // the whole runs before the signal.
  gimbalsim::io::installStopHandlers();
  opt.stop_requested = gimbalsim::io::stopRequested;
  for (const Planned& p : scenes) {
    if (gimbalsim::io::stopRequested()) break;
    runs.push_back(pointing_study::runOne(p.scene, cfg, opt, p.scene_name, p.label, p.clearance, p.sensors));
    if (runs.back().interrupted) {
      runs.pop_back();
      break;
    }
    const Study& s = runs.back();
    std::printf("%-34s %-18s %11.3g %13s %13s %13s  %s\n", s.label.c_str(), s.scene.c_str(), s.clearance,
                pointing::figureText(s.peak_track, s.track_reason, "%.4e").c_str(),
                pointing::figureText(s.rms_track, s.track_reason, "%.4e").c_str(),
                pointing::figureText(s.peak_run,
                                     s.run_reason.empty() ? "" : s.err.empty() ? "no tick" : "first step failed",
                                     "%.4e").c_str(),
                s.ok ? "ok" : ("stop: " + s.reason).c_str());
    std::fflush(stdout);
  }
  files[0]->write(config_text);
  files[1]->write(pointing_study::timeSeriesCsv(runs, cfg.period));
  files[2]->write(pointing_study::summaryCsv(runs));
  if (gimbalsim::io::CommitGroup group({files[0].get(), files[1].get(), files[2].get()}); !group.commit()) {
    std::fprintf(stderr, "gimbalsim_pointing_study: error: %s\n", group.error().c_str());
    return kExitWrite;
  }
  std::printf("wrote %s, %s, %s\n", (dir / "pointing_error.csv").c_str(), (dir / "summary.csv").c_str(),
              (dir / "config.txt").c_str());
  if (gimbalsim::io::stopRequested()) {
    std::fprintf(stderr, "gimbalsim_pointing_study: interrupted by %s after %zu whole runs\n",
                 gimbalsim::io::stopSignalName(), runs.size());
    return gimbalsim::io::stopExitCode();
  }
  const bool all_ok = std::all_of(runs.begin(), runs.end(), [](const Study& s) { return s.ok; });
  return all_ok ? 0 : kExitStopped;
}

}  // namespace

int main(int argc, char** argv) {
  return program::guardedMain("gimbalsim_pointing_study", [&] { return mainImpl(argc, argv); });
}
