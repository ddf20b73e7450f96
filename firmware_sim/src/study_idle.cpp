#include "gimbalsim/firmware_sim/study_idle.hpp"

#include <algorithm>
#include <initializer_list>
#include <string>
#include <vector>

#include "gimbalsim/firmware_sim/fault_schedule_io.hpp"
#include "gimbalsim/input/value_format.hpp"

namespace gimbalsim::firmware {

const std::vector<std::pair<std::string, std::string>>& closedLoopIdleSceneKeys() {
  static const std::vector<std::pair<std::string, std::string>> kIdle = {
      {"sim.output_interval", "the closed loop records every control period"},
      {"torque.tau1", "the controller commands the torque"},
      {"torque.tau2", "the controller commands the torque"},
      // only dynamics/src/simulate.cpp's InvariantMonitor reads them; this loop steps without one
      {"sim.momentum_tol", "the closed loop checks no invariant: only an open-loop run stops on it"},
      {"sim.energy_tol", "the closed loop checks no invariant: only an open-loop run stops on it"},
      {"name", "the scene's label: no run reads it"}};
  return kIdle;
}

const std::vector<std::pair<std::string, std::string>>& closedLoopIdleControllerKeys() {
  // closed_loop.cpp answers every status with an attitude of the same tick, and a study has no fault schedule
  static const std::string kNeverStale =
      "a study's closed loop delivers every status with the attitude of its own tick and injects no fault: no "
      "status is stale (the bench's --faults can make one)";
  static const std::vector<std::pair<std::string, std::string>> kIdle = {{"monitor.stale_ticks", kNeverStale},
                                                                         {"monitor.hold_ticks", kNeverStale}};
  return kIdle;
}

std::string closedLoopIdleSceneKey(const std::string& key) {
  for (const auto& [idle, why] : closedLoopIdleSceneKeys()) {
    if (key == idle) return why;
  }
  return "";
}

std::string idleSceneOverride(const char* flag, const std::vector<std::string>& overrides) {
  for (std::size_t k = 0; k < overrides.size(); ++k) {
    if (const std::string why = closedLoopIdleSceneKey(overrides[k].substr(0, overrides[k].find('=')));
        !why.empty()) {
      return std::string(flag) + " #" + std::to_string(k + 1) + " '" + overrides[k] + "': not read by the closed " +
             "loop (" + why + "): the value would be recorded but never act";
    }
  }
  return "";
}

std::string sensorKeyIdle(const std::string& key, const SensorParams& sp, const SensorRun& run) {
  const double duration_s = run.duration_s, T = run.period_s;
  const auto one_of = [&](std::initializer_list<const char*> keys) {
    return std::any_of(keys.begin(), keys.end(), [&](const char* k) { return key == std::string("sensors.") + k; });
  };
  const Vec2& star_outage = sp.star_tracker_outage;
  const bool outage_key = key == "sensors.star_tracker_outage" && star_outage(1) > star_outage(0);
  if (outage_key || one_of({"star_tracker_rate", "star_tracker_latency"})) {
    // a gyro jump matters where it acts by the outage's next sample (pass 93), or anywhere for a rate or latency
    const double jump_by =
        outage_key && T > 0.0 ? starSampleDeliveredFrom(sp, star_outage(1) + T, T) + T : duration_s;
    const bool jump = run.faults != nullptr && T > 0.0 && gyroJumpActsBefore(*run.faults, jump_by, duration_s, T);
    if (std::string why = starTrackerRedundant(sp, run.floating_base, jump); !why.empty()) return why;
  }
  // (pass 93) an outage between two samples, or whose samples fall due after the run, holds none: as the fault's
  const auto holds_none = [&](const SampledSensor& s, const Vec2& outage) {
    return T > 0.0 && outage(1) > outage(0) && outage(0) < duration_s &&
           !windowHoldsASample(s, WindowActsOn::Both, outage(0), outage(1), true, duration_s, T, run.last_tick_acts);
  };
  if (outage_key && holds_none(starTrackerSampling(sp), star_outage)) {
    return "sensors.star_tracker_outage " +
           windowHoldsNoSample(starTrackerSampling(sp), WindowActsOn::Both, star_outage(0), star_outage(1), true);
  }
  if (key.rfind("sensors.tracker_", 0) == 0 || key.rfind("sensors.antenna_gyro_", 0) == 0) {
    if (!sp.antenna_sensors) return "the run has no antenna sensor (sensors.antenna none): nothing reads it";
    if (!run.antenna_loop) return "the controller does not close its loop at the antenna (antenna.tracker ignore)";
  }
  // (pass 97) and the boresight tracker's, as the star tracker's
  if (key == "sensors.tracker_outage" && holds_none(boresightTrackerSampling(sp), sp.tracker_outage)) {
    return "sensors.tracker_outage " + windowHoldsNoSample(boresightTrackerSampling(sp), WindowActsOn::Both,
                                                           sp.tracker_outage(0), sp.tracker_outage(1), true);
  }
  // (pass 78) an outage over the whole run takes no sample: what acts only through samples acts on nothing
  const auto whole_run = [&](const Vec2& outage) {
    return outage(1) > outage(0) && outage(0) <= 0.0 && outage(1) >= duration_s;
  };
  const auto covered = [&](const char* name, const Vec2& outage) {
    return "sensors." + std::string(name) + "_outage [" + formatNumber(outage(0)) + ", " + formatNumber(outage(1)) +
           "] s covers the whole run (" + formatNumber(duration_s) + " s): no sample of it is taken";
  };
  // (pass 88) an outage from the run's end on holds no sample: it was recorded as the runs' sensors
  const auto after_end = [&](const char* name, const Vec2& outage) {
    return "sensors." + std::string(name) + "_outage [" + formatNumber(outage(0)) + ", " + formatNumber(outage(1)) +
           "] s starts at or after the run's end (" + formatNumber(duration_s) + " s): no sample falls in it";
  };
  if (key == "sensors.star_tracker_outage" && sp.star_tracker_outage(0) >= duration_s) {
    return after_end("star_tracker", sp.star_tracker_outage);
  }
  if (key == "sensors.tracker_outage" && sp.tracker_outage(0) >= duration_s) {
    return after_end("tracker", sp.tracker_outage);
  }
  if (one_of({"star_tracker_noise", "star_tracker_rate", "star_tracker_latency"}) &&
      whole_run(sp.star_tracker_outage)) {
    return covered("star_tracker", sp.star_tracker_outage);
  }
  if (one_of({"tracker_noise", "tracker_bias", "tracker_rate", "tracker_latency"}) && whole_run(sp.tracker_outage)) {
    return covered("tracker", sp.tracker_outage);
  }
  // (passes 103, 105) and one over every sample the run takes, short of its end (a 0.2 Hz tracker's one sample
  // at 0 s in [0, 3.99] of a 4 s run): the noise and bias act on none (a rate or a latency decides which samples
  // the window holds: it acts)
  // (passes 103, 107) with the bench's --faults outages of the sensor too (every one certain: probability 1)
  const auto loses_all = [&](const SampledSensor& s, const char* name, const Vec2& outage, FaultKind kind) {
    std::vector<OutageWindow> outages;
    std::vector<std::string> named;
    if (outage(1) > outage(0)) {
      outages.push_back({outage(0), outage(1), true});
      named.push_back("sensors." + std::string(name) + "_outage [" + formatNumber(outage(0)) + ", " +
                      formatNumber(outage(1)) + "] s");
    }
    for (std::size_t i = 0; run.faults != nullptr && i < run.faults->faults.size(); ++i) {
      const FaultSpec& f = run.faults->faults[i];
      if (f.kind != kind || f.probability < 1.0 || !(f.end > f.start)) continue;
      outages.push_back({f.start, f.end, false});
      named.push_back("fault #" + std::to_string(i + 1) + " (" + faultTypeName(kind) + ") [" + formatNumber(f.start) +
                      ", " + formatNumber(f.end) + ") s");
    }
    if (!outagesLoseEverySample(s, outages, duration_s, T)) return std::string();
    return join(named, " and ") + (named.size() > 1 ? " take or drop" : " takes or drops") + " every " + s.name +
           " sample that would act in the run (one every " + formatNumber(1.0 / s.rate) + " s, latency " +
           formatNumber(s.latency) + " s): none acts";
  };
  if (one_of({"star_tracker_noise"})) {
    if (std::string why = loses_all(starTrackerSampling(sp), "star_tracker", sp.star_tracker_outage,
                                    FaultKind::StarTrackerOutage);
        !why.empty()) {
      return why;
    }
  }
  if (one_of({"tracker_noise", "tracker_bias"})) {
    if (std::string why =
            loses_all(boresightTrackerSampling(sp), "tracker", sp.tracker_outage, FaultKind::TrackerOutage);
        !why.empty()) {
      return why;
    }
  }
  // (pass 97) a latency that delivers even the first sample (at 0 s) at the run's last tick or after (pass 99: at
  // it, no command answers it) lets none act, and what acts only through the samples acts on nothing (the latency
  // itself acts: without it they would arrive)
  const auto none_arrives = [&](const SampledSensor& s) {
    const double first = T > 0.0 ? firstTickAtOrAfter(s.latency, T) * T : s.latency;
    if (!(first >= duration_s - 1e-9 * (T > 0.0 ? T : first))) return std::string();
    return std::string(s.rate_key) + "_latency " + formatNumber(s.latency) + " s delivers the first " + s.name +
           " sample at the run's last tick or after (" + formatNumber(duration_s) + " s): none acts";
  };
  if (one_of({"star_tracker_noise", "star_tracker_rate"})) return none_arrives(starTrackerSampling(sp));
  if (one_of({"tracker_noise", "tracker_bias", "tracker_rate"})) return none_arrives(boresightTrackerSampling(sp));
  return "";
}

std::string idleInEveryRun(const char* flag, const std::vector<std::string>& overrides,
                           const std::vector<StudyScene>& runs, std::vector<std::string>* partly) {
  for (std::size_t k = 0; k < overrides.size(); ++k) {
    const std::string key = overrides[k].substr(0, overrides[k].find('='));
    std::string why, scenes;
    std::size_t idle_runs = 0;
    for (const StudyScene& r : runs) {
      const auto& idle = r.scene->idle_sets;
      const auto it = std::find_if(idle.begin(), idle.end(),
                                   [&](const auto& s) { return s.first == r.first_set + static_cast<int>(k); });
      const std::string sensor_why = it != idle.end() || !r.sensors ? "" : sensorKeyIdle(key, *r.sensors, r.run);
      if (it == idle.end() && sensor_why.empty()) continue;
      ++idle_runs;
      const std::string reason = it != idle.end() ? it->second : "key '" + key + "': " + sensor_why;
      if (why.find(reason) == std::string::npos) why += (why.empty() ? "" : "; ") + reason;
      // a scene without clearance (the ideal reference) has no bearing by design: not worth a warning; a sensor
      // key idle in some runs is, named with their sensors (pass 91: the perfect runs of --sensors both)
      const bool scene_idle = it != idle.end();
      const std::string run =
          "'" + r.name + "'" + (scene_idle || r.sensors_label.empty() ? "" : " (" + r.sensors_label + ")");
      if ((!scene_idle || r.scene->model.hasClearance()) && scenes.find(run) == std::string::npos) {
        scenes += (scenes.empty() ? "" : ", ") + run;
      }
    }
    if (idle_runs == 0) continue;
    const std::string named = std::string(flag) + " #" + std::to_string(k + 1) + " '" + overrides[k] + "'";
    if (idle_runs == runs.size()) {
      return named + ": acts in no run of this study (" + why + "): the value would be recorded but never act";
    }
    if (!scenes.empty()) partly->push_back(named + ": acts on nothing in the runs of " + scenes + " (" + why + ")");
  }
  return "";
}

std::string idleSeedOverride(const char* flag, const std::vector<std::string>& overrides, bool any_noise) {
  if (any_noise) return "";
  for (std::size_t k = 0; k < overrides.size(); ++k) {
    if (overrides[k].substr(0, overrides[k].find('=')) != "sensors.seed") continue;
    return std::string(flag) + " #" + std::to_string(k + 1) + " '" + overrides[k] + "': no run of this study " +
           "draws sensor noise (sensors.encoder_noise, rate_noise, gyro_noise, gyro_bias_walk, star_tracker_noise " +
           "and the antenna's tracker_noise, antenna_gyro_noise are 0): the seed would be recorded but never act";
  }
  return "";
}

}  // namespace gimbalsim::firmware
