// controller_sweep: the gain sweep in one process (library + dynamics, no LCM):
// for each closed-loop bandwidth omega, triple-pole gains on both axes
// (pid.hpp triplePoleGains with the configured inertias), one closed-loop run,
// one table row: settling time, tracking errors, peak torque.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/controllers/pointing_controller.hpp"
#include "gimbalsim/input/input_error.hpp"
#include "gimbalsim/input/key_registry.hpp"
#include "gimbalsim/firmware_sim/closed_loop.hpp"
#include "gimbalsim/controllers/key_use.hpp"
#include "gimbalsim/firmware_sim/study_idle.hpp"
#include "gimbalsim/pointing/profile_windows.hpp"
#include "gimbalsim/program/program.hpp"

using namespace gimbalsim;
using namespace gimbalsim::controllers;
using firmware::ClosedLoopOptions;
using firmware::ClosedLoopResult;

namespace {

// The keys the sweep sets from each --omega: each axis's triple-pole gains (a --set of one is refused).
constexpr std::array<const char*, 2> kAxisPrefixes{"azimuth.", "elevation."};
constexpr std::array<const char*, 3> kGainKeys{"kp", "ki", "kd"};

int mainImpl(int argc, char** argv) {
  CLI::App app{"In-process gain sweep of the pointing controller on a scene"};
  std::string scene_path, config_path;
  std::vector<std::string> scene_sets, sets;
  std::vector<double> omegas{5, 10, 20, 40};
  ClosedLoopOptions opt;
  opt.duration = 0.0;
  app.add_option("--scene", scene_path, "scene file")->required();
  app.add_option("--config", config_path, "controller configuration file")->required();
  app.add_option("--scene-set", scene_sets, "scene override key=value");
  app.add_option("--set", sets, "controller override key=value");
  app.add_option("--omega", omegas, "closed-loop bandwidths [rad/s] (triple pole)")->delimiter(',')
      ->check(program::within(1e-3, 1e6));  // below 1e-3 rad/s the gains underflowed to 0 (1e-300: kp = 0)
  app.add_option("--duration", opt.duration, "simulated time [s] (default: the track start + 5 s)")
      ->check(program::within(0.0, 1e9, true));  // -1 ran the default silently
  app.add_option("--settle-tol", opt.settle_tol, "settling band on the joint error [rad]")
      ->check(program::within(0.0, 10.0, true));
  if (const auto rc = program::parse(app, argc, argv, "controller_sweep")) return *rc;
  if (const std::string why = program::repeatedValue("--omega", omegas); !why.empty()) {
    return program::refuse("controller_sweep", why);
  }
  if (const std::string why = program::overrideOfOwnKey("--scene-set", scene_sets, {{"sim.duration", "--duration"}});
      !why.empty()) {
    return program::refuse("controller_sweep", why);
  }
  // Keys the closed loop never reads: recorded with the runs, acting on none (pass 66: torque.tau1=1000 ran as 0).
  if (const std::string why = firmware::idleSceneOverride("--scene-set", scene_sets); !why.empty()) {
    return program::refuse("controller_sweep", why);
  }
  // The loaders number their overrides --set #k: the scene's are this program's --scene-set #k.
  std::vector<std::string> scene_labels;
  for (std::size_t k = 0; k < scene_sets.size(); ++k) {
    scene_labels.push_back("--scene-set #" + std::to_string(k + 1) + " '" + scene_sets[k] + "'");
  }
  try {
    const firmware::PlantScene ps = [&] {
      try {
        return firmware::loadPlantScene(scene_path, firmware::closedLoopOverrides(scene_sets));
      } catch (const InputError& e) {
        throw InputError(relabelledProblems(e, scene_labels));
      }
    }();
    // A seed with no noise to draw: recorded with the runs, acting on none.
    if (const std::string why = firmware::idleSeedOverride("--scene-set", scene_sets, ps.sensors.anyNoise());
        !why.empty()) {
      return program::refuse("controller_sweep", why);
    }
    const Model& m = ps.scene.model;
    const ControllerConfig base = loadControllerConfig(config_path, sets);
    if (opt.duration <= 0.0) opt.duration = base.profile.trackStart() + 5.0;
    if (const std::string why = firmware::controlPeriodProblem(ps, base.period); !why.empty()) {
      return program::refuse("controller_sweep", "--config/--set " + why);
    }
    // The loop runs whole control periods: a duration between two is refused, not rounded.
    if (const std::string why = wholeMultipleProblem(opt.duration, base.period, "the control period (control.period)");
        !why.empty()) {
      return program::refuse("controller_sweep", "--duration: " + why);
    }
    // Its figures are the tracking errors: a run that never reaches the track is refused before any work.
    if (const std::string why = pointing::windowNotReached(
            pointing::profileWindow(base.profile, pointing::Segment::Track), pointing::WindowNeed::Part, opt.duration);
        !why.empty()) {
      return program::refuse("controller_sweep", "--duration: " + why + " (the table's figures are over the track)");
    }
    // A --scene-set the scene's joints leave idle (joint 1's friction on an ideal joint 1): every run would
    // record it and none act (pass 72); a sensor key too (pass 78).
    std::vector<std::string> partly_idle;  // one scene: idle in some runs is idle in all
    const firmware::StudyScene run{
        scene_path, &ps.scene, 1, &ps.sensors,
        {opt.duration, base.period, base.antenna.use_tracker, ps.scene.model.floating_base, nullptr}, ""};
    if (const std::string why = firmware::idleInEveryRun("--scene-set", scene_sets, {run}, &partly_idle);
        !why.empty()) {
      return program::refuse("controller_sweep", why);
    }
    // A --set the loop never reads would be recorded with the table and act on nothing (pass 80).
    if (const std::string why = idleControllerOverride("--set", sets, base, ps.sensors.antenna_sensors,
                                                       firmware::closedLoopIdleControllerKeys());
        !why.empty()) {
      return program::refuse("controller_sweep", why);
    }
    // The sweep sets each axis's kp, ki and kd from --omega: a --set of one was overwritten, the row the same as
    // without it (pass 86).
    for (std::size_t k = 0; k < sets.size(); ++k) {
      std::string key = sets[k].substr(0, sets[k].find('='));
      key.erase(key.find_last_not_of(" \t") + 1);
      for (const char* axis : kAxisPrefixes) {
        const auto gain = std::find_if(kGainKeys.begin(), kGainKeys.end(),
                                       [&](const char* g) { return key == std::string(axis) + g; });
        if (gain == kGainKeys.end()) continue;
        return program::refuse("controller_sweep", "--set #" + std::to_string(k + 1) + " '" + sets[k] + "': the sweep "
                               "sets " + key + " from each --omega (triple-pole gains): the value would act on no run");
      }
    }
    // Each bandwidth's gains go through the configuration's own key checks
    // (--omega 1e300 gave kp = 5e601 and a NaN command): refused, nothing run.
    std::vector<ControllerConfig> configs;
    for (double w : omegas) {
      std::vector<std::string> with_gains = sets;
      std::vector<std::string> labels;  // a refusal names the user's --set by its count, a gain by --omega
      for (std::size_t k = 0; k < sets.size(); ++k) labels.push_back("--set #" + std::to_string(k + 1) + " '" + sets[k] + "'");
      std::vector<std::pair<std::string, std::string>> gains;  // (key, its label)
      for (int i = 0; i < 2; ++i) {
        const AxisGains g = triplePoleGains(base.axis[i].inertia, w, base.axis[i].torque_limit, base.axis[i].aw_gain);
        const std::string axis = kAxisPrefixes[i];
        const double values[] = {g.kp, g.ki, g.kd};  // kGainKeys' order
        for (std::size_t j = 0; j < kGainKeys.size(); ++j) {
          const std::string key = kGainKeys[j], value = formatNumber(values[j]);  // reads back as the same gain
          with_gains.push_back(axis + key + "=" + value);
          labels.push_back("--omega " + formatNumber(w) + " gives " + axis + key + " = " + value);
          gains.emplace_back(axis + key, labels.back());
        }
      }
      try {
        configs.push_back(loadControllerConfig(config_path, with_gains));
      } catch (const InputError& e) {
        const std::vector<std::string> problems = relabelledProblems(e, labels);
        std::string refused;  // the gains refused, named on the last line too
        for (const auto& gain : gains) {
          const bool named = std::any_of(problems.begin(), problems.end(),
                                         [&](const std::string& p) { return p.rfind(gain.second, 0) == 0; });
          if (named) refused += (refused.empty() ? "" : ", ") + gain.first;
        }
        for (const std::string& p : problems) std::fprintf(stderr, "error: %s\n", p.c_str());
        return program::refuse("controller_sweep", "--omega " + formatNumber(w) + ": its triple-pole gains " +
                               (refused.empty() ? std::string("are") : "(" + refused + ") are") +
                               " outside the configuration's ranges");
      }
    }
    std::printf("# scene %s, %g s, settle band %g rad, torque limit %g / %g N m\n", m.name.c_str(), opt.duration,
                opt.settle_tol, base.axis[0].torque_limit, base.axis[1].torque_limit);
    std::printf("%8s %9s %9s %9s %11s %11s %11s %11s %9s %9s\n", "omega", "kp_az", "kd_az", "ki_az", "settle[s]",
                "max_e_trk", "max_truth", "rms_truth", "tau1max", "tau2max");
    int failures = 0;
    for (std::size_t k = 0; k < omegas.size(); ++k) {
      const double w = omegas[k];
      const ControllerConfig& c = configs[k];
      PointingController controller(c);
      const ClosedLoopResult r = firmware::runClosedLoop(ps, controller, c.profile, opt);
      if (!r.ok) {
        std::printf("%8g  stopped: %s\n", w, r.error.c_str());
        ++failures;
        continue;
      }
      using pointing::figureText;
      std::printf("%8g %9.4g %9.4g %9.4g %11s %11s %11s %11s %9.4g %9.4g\n", w, c.axis[0].kp, c.axis[0].kd,
                  c.axis[0].ki, figureText(r.settle_time, r.settle_reason, "%.4g").c_str(),
                  figureText(r.max_joint_error_track, r.track_reason, "%.3e").c_str(),
                  figureText(r.max_truth_error_track, r.track_reason, "%.3e").c_str(),
                  figureText(r.rms_truth_error_track, r.track_reason, "%.3e").c_str(), r.max_abs_tau(0),
                  r.max_abs_tau(1));
    }
    return failures ? program::kStopped : program::kOk;
  } catch (const InputError& e) {
    return program::refuse("controller_sweep", e);
  }
}

}  // namespace

int main(int argc, char** argv) {
  return program::guardedMain("controller_sweep", [&] { return mainImpl(argc, argv); });
}
