// Reading a fault schedule (fault_schedule.hpp) from YAML: the edge, never
// the tick. The file is a list of faults, so it has its own small reader over
// the key registry's converters (asNumber, asInt, asVector, asChoice:
// gimbalsim/input/key_registry.hpp) and yaml-cpp's marks; every problem
// is collected and names file:line:column, the entry and the key, as the
// scene loader does. Format: README "Fault schedule".
#pragma once

#include <string>
#include <vector>

#include "gimbalsim/dynamics/run_spec.hpp"
#include "gimbalsim/input/input_error.hpp"
#include "gimbalsim/scene/scene.hpp"
#include "gimbalsim/firmware_sim/fault_schedule.hpp"
#include "gimbalsim/firmware_sim/sensor_params.hpp"
#include "gimbalsim/firmware_sim/plant_scene.hpp"

namespace gimbalsim::firmware {

/// A refused schedule: every problem, each naming place, entry and key.
class FaultScheduleError : public InputError {
 public:
  using InputError::InputError;
};

/// Loads and checks a schedule file (throws FaultScheduleError).
FaultSchedule loadFaultSchedule(const std::string& path);
/// Same, from YAML text (`origin` names it in messages).
FaultSchedule loadFaultScheduleText(const std::string& yaml, const std::string& origin);

/// The checks that need the scene (bearing wear and friction rise need the
/// clearance joint, a wear clearance above the scene's and below the bearing
/// radius, friction rise a friction law; the tracker's faults the antenna
/// sensors): problems naming origin:line, the entry and the key; empty when fine.
std::vector<std::string> checkFaultsAgainstScene(const FaultSchedule& s, const PlantScene& ps, const std::string& origin);

/// The checks that need the run's length [s] and its tick period [s]: a schedule whose every fault starts after
/// the run's end would act in no tick while the run was recorded with it (pass 73), and so would a fault (not a
/// ramp, which holds from its start) whose [start, end) falls between two ticks (pass 78); a run cut short of
/// some of its faults is a run of the others. Problems as above, empty when fine.
std::vector<std::string> checkFaultsAgainstDuration(const FaultSchedule& s, double duration, double tick_period,
                                                    const std::string& origin);

/// Each star tracker outage that takes and delivers no sample of the scene's tracker in its ticks (up to the run's
/// end), or whose samples tell nothing (starTrackerRedundant: a fixed base, perfect attitude sensors and no
/// gyro_bias_jump acting before the outage's first sample after it): it would change nothing but its flag
/// (fault_samples.cpp).
std::vector<std::string> checkFaultsAgainstSamples(const FaultSchedule& s, const PlantScene& ps, double duration,
                                                   double tick_period, const std::string& origin);

/// Whether a gyro_bias_jump of s takes a step in a run of duration [s] at tick_period [s] and starts before
/// t_before [s]: a jump moves the estimate from its start on (the star tracker then corrects it).
bool gyroJumpActsBefore(const FaultSchedule& s, double t_before, double duration, double tick_period);

/// The tick [s] at which the first star tracker sample belonging to t [s] or later is delivered.
double starSampleDeliveredFrom(const SensorParams& p, double t, double tick_period);

/// Whether a star tracker outage from start to end [s] ([start, end) for a fault, [start, end] with
/// end_inclusive for the scene key sensors.star_tracker_outage) takes a sample that would be delivered within a
/// run of duration [s], or drops one due in it; false: it would change nothing but its flag.
bool starOutageDropsASample(const SensorParams& p, double start, double end, bool end_inclusive, double duration,
                            double tick_period);

/// Why a star tracker outage from start to end [s] (closed as starOutageDropsASample's end_inclusive) is refused
/// when it drops no sample: "[start, end) s takes and delivers no star tracker sample (...)".
std::string starOutageHoldsNoSample(const SensorParams& p, double start, double end, bool end_inclusive);

}  // namespace gimbalsim::firmware
