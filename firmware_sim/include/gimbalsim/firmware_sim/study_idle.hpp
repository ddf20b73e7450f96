#pragma once
// What a closed-loop study's overrides act on: the judges the study programs
// (pointing_study, controller_floor, controller_sweep) and the Python sweeps
// run before any run, so that a value recorded with every run also acts in one.

#include <string>
#include <utility>
#include <vector>

#include "gimbalsim/firmware_sim/fault_schedule.hpp"
#include "gimbalsim/firmware_sim/sensor_params.hpp"
#include "gimbalsim/scene/scene.hpp"

namespace gimbalsim::firmware {

/// The scene keys runClosedLoop never reads, each with why: sim.output_interval
/// (it records every control period), torque.tau1/tau2 (the controller commands
/// the torque), sim.momentum_tol/energy_tol (no invariant is checked), name.
/// The one list: the study programs and the Python sweeps and tuner refuse these.
const std::vector<std::pair<std::string, std::string>>& closedLoopIdleSceneKeys();

/// The controller keys runClosedLoop never lets act, each with why: monitor.stale_ticks and hold_ticks (every
/// status carries the attitude of its own tick and no fault delays one: none is ever stale). The one list: the
/// study programs and the Python sweeps and tuner refuse these.
const std::vector<std::pair<std::string, std::string>>& closedLoopIdleControllerKeys();

/// Why runClosedLoop never reads the scene key `key` (closedLoopIdleSceneKeys), or "" when it reads it.
std::string closedLoopIdleSceneKey(const std::string& key);

/// The first of `overrides` (key=value) that runClosedLoop never reads
/// (closedLoopIdleSceneKeys), as a refusal naming `flag` #k and why ("" when
/// none). A study's override of one would be recorded with its runs and never act.
std::string idleSceneOverride(const char* flag, const std::vector<std::string>& overrides);

/// What sensorKeyIdle needs of a run besides its sensors.
struct SensorRun {
  double duration_s = 0.0;               ///< [s] the run's length
  double period_s = 0.0;                 ///< [s] its tick (0: the star tracker's samples are not judged)
  bool antenna_loop = false;             ///< the controller closes at the antenna (antenna.tracker)
  bool floating_base = true;             ///< structure.base floating
  const FaultSchedule* faults = nullptr;  ///< the bench's --faults (a study has none)
  bool last_tick_acts = false;            ///< closed_loop: its last row records the estimate (windowHoldsASample)
};

/// One run of a study as idleInEveryRun sees it: the scene it ran (its file's name) and the loader's number
/// (1-based) of the study's first `flag` value among the overrides that scene was loaded with.
struct StudyScene {
  std::string name;
  const Scene* scene = nullptr;
  int first_set = 1;
  const SensorParams* sensors = nullptr;  ///< the run's sensors, for sensorKeyIdle (none: not judged)
  SensorRun run;                          ///< its length, control period, loop and base, for sensorKeyIdle
  std::string sensors_label;              ///< the run's sensors as the study labels them ("" one kind)
};

/// Why the sensor key `key` acts on nothing in a closed-loop run of duration_s [s] on sensors sp ("" when it
/// can act): an antenna key (sensors.tracker_*, antenna_gyro_*) where the run has no antenna sensor or its
/// controller does not close at the antenna (antenna_loop false), or a key acting only through the star
/// tracker's or boresight tracker's samples under an outage over the whole run (none is taken), a star tracker
/// outage that takes and delivers no sample, or where the star tracker tells nothing (starTrackerRedundant: a
/// fixed base, a perfect gyro, no gyro_bias_jump in run.faults acting by the outage's next sample).
std::string sensorKeyIdle(const std::string& key, const SensorParams& sp, const SensorRun& run);

/// The study's `flag` values (key=value) that the scene loader found acting on nothing (Scene::idle_sets), or
/// sensorKeyIdle for a run whose sensors are given:
/// a refusal naming the first one that acts in no run and why (it would be recorded with every run and act
/// on none), else "". Each one idle in some runs only is told in *partly, naming those runs' scenes that have
/// clearance (the ideal reference has no bearing by design), or, for a sensor key, the runs with their sensors.
std::string idleInEveryRun(const char* flag, const std::vector<std::string>& overrides,
                           const std::vector<StudyScene>& runs, std::vector<std::string>* partly);

/// A `sensors.seed` among `overrides` when no run of the study draws sensor
/// noise (any_noise false: SensorParams::anyNoise of every run), as a refusal
/// naming `flag` #k ("" otherwise): the seed would be recorded and never act.
std::string idleSeedOverride(const char* flag, const std::vector<std::string>& overrides, bool any_noise);

}  // namespace gimbalsim::firmware
