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

/// The first axis (0 azimuth, 1 elevation) a torque_limit fault acts on whose limit_Nm(axis) [N m] (the motor's,
/// the controller's) it is not below: there it clips nothing. -1 when it clips on each, or is no torque_limit.
int torqueLimitClipsNothingOn(const FaultSpec& f, const Vec2& limit_Nm);

/// The checks that need the run's length [s] and its tick period [s]: a schedule whose every fault starts after
/// the run's end would act in no tick while the run was recorded with it (pass 73), and so would a fault (not a
/// ramp, which holds from its start) whose [start, end) falls between two ticks (pass 78); a run cut short of
/// some of its faults is a run of the others. Problems as above, empty when fine.
std::vector<std::string> checkFaultsAgainstDuration(const FaultSchedule& s, double duration, double tick_period,
                                                    const std::string& origin);

/// Each fault on a sampled sensor that touches none of its samples in its ticks (up to the run's end): a star
/// tracker or boresight tracker outage that takes and delivers none, a tracker_bias that biases no reading taken,
/// a tracker_dropout with no reading due; or a star tracker outage whose samples tell nothing
/// (starTrackerRedundant: a fixed base, perfect attitude sensors and no gyro_bias_jump acting before the
/// outage's first sample after it): it would change nothing but its flag (fault_samples.cpp).
/// last_tick_acts as windowHoldsASample's.
std::vector<std::string> checkFaultsAgainstSamples(const FaultSchedule& s, const PlantScene& ps, double duration,
                                                   double tick_period, const std::string& origin,
                                                   bool last_tick_acts);

/// Whether a gyro_bias_jump of s takes a step in a run of duration [s] at tick_period [s] and starts before
/// t_before [s]: a jump moves the estimate from its start on (the star tracker then corrects it).
bool gyroJumpActsBefore(const FaultSchedule& s, double t_before, double duration, double tick_period);

/// The tick [s] at which the first star tracker sample belonging to t [s] or later is delivered.
double starSampleDeliveredFrom(const SensorParams& p, double t, double tick_period);

/// A sensor sampled as sample_schedule.hpp takes and delivers: sample j belongs to j / rate [s], is taken at
/// the first tick at or after it and delivered at the first tick at or after j / rate + latency.
struct SampledSensor {
  const char* name;      ///< "star tracker", "boresight tracker"
  const char* rate_key;  ///< its scene keys' prefix: "sensors.star_tracker", "sensors.tracker"
  double rate = 0.0;     ///< [Hz]
  double latency = 0.0;  ///< [s]
};
SampledSensor starTrackerSampling(const SensorParams& p);
SampledSensor boresightTrackerSampling(const SensorParams& p);

/// What a window of a sampled sensor acts on: the samples taken in it (an outage loses them, a bias biases them),
/// the deliveries due in it (an outage or a dropout drops them), or both.
enum class WindowActsOn { Takes, Deliveries, Both };

/// Whether a window from start to end [s] ([start, end) for a fault, [start, end] with end_inclusive for a
/// scene key's outage) holds a sample taken in it that would be delivered within a run of duration [s], or a
/// delivery due in it, as `acts` asks; false: it would change nothing but its flag. last_tick_acts: a delivery
/// at the run's last tick acts (closed_loop's last row records the estimate); on the bench and in the studies
/// no command answers it (pass 103).
bool windowHoldsASample(const SampledSensor& s, WindowActsOn acts, double start, double end, bool end_inclusive,
                        double duration, double tick_period, bool last_tick_acts);

/// An outage of a sampled sensor: [start, end] [s] for a scene key's (end_inclusive), [start, end) for a fault's.
struct OutageWindow {
  double start = 0.0, end = 0.0;
  bool end_inclusive = true;
};

/// Whether the outages together lose every sample of s that would act in a run of duration [s] at tick_period
/// [s]: each taken or delivered in one of them, or delivered at the run's last tick or after (no command answers
/// it). False when not judged (no outage, no period, more than 1e6 samples).
bool outagesLoseEverySample(const SampledSensor& s, const std::vector<OutageWindow>& outages, double duration,
                            double tick_period);
/// The same for one scene key's outage [start, end].
inline bool windowLosesEverySample(const SampledSensor& s, double start, double end, double duration,
                                   double tick_period) {
  return outagesLoseEverySample(s, {{start, end, true}}, duration, tick_period);
}

/// Why such a window is refused: "[start, end) s takes and delivers no star tracker sample (one every P s,
/// sensors.star_tracker_rate; latency L s): it would change nothing but its flag".
std::string windowHoldsNoSample(const SampledSensor& s, WindowActsOn acts, double start, double end,
                                bool end_inclusive);

}  // namespace gimbalsim::firmware
