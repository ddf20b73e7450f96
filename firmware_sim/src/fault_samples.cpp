// A star tracker outage in the fault schedule against the tracker's samples
// (attitude_sensors.hpp: sample j belongs to j P and is taken in the first tick
// at or after it, delivered in the first tick at or after t_s + latency).
#include <algorithm>
#include <cmath>

#include "gimbalsim/firmware_sim/fault_schedule_io.hpp"
#include "gimbalsim/input/value_format.hpp"

namespace gimbalsim::firmware {

// (pass 87) an outage between two 10 Hz samples dropped none: only its flag changed, recorded as injected.
bool gyroJumpActsBefore(const FaultSchedule& s, double t_before, double duration, double tick_period) {
  const double T = tick_period, tol = 1e-9 * tick_period;
  return std::any_of(s.faults.begin(), s.faults.end(), [&](const FaultSpec& g) {
    return g.kind == FaultKind::GyroBiasJump && g.start < t_before &&
           firstTickAtOrAfter(g.start, T) * T < duration - tol;
  });
}

std::vector<std::string> checkFaultsAgainstSamples(const FaultSchedule& s, const PlantScene& ps, double duration,
                                                   double tick_period, const std::string& origin) {
  std::vector<std::string> out;
  const SensorParams& p = ps.sensors;
  const double T = tick_period, tol = 1e-9 * tick_period, P = 1.0 / p.star_tracker_rate;
  if (!(T > 0.0) || !(P > 0.0)) return out;
  for (std::size_t i = 0; i < s.faults.size(); ++i) {
    const FaultSpec& f = s.faults[i];
    // (pass 89) on a fixed base with perfect sensors the estimate is exact without a sample, unless a gyro bias
    // jump acts before the first sample after the outage (passes 90-91: a jump after it, or after the run's end,
    // let the outage through)
    if (f.kind == FaultKind::StarTrackerOutage) {
      const double next_sample = f.end + P + p.star_tracker_latency + T;
      const std::string why = starTrackerRedundant(p, ps.scene.model.floating_base,
                                                   gyroJumpActsBefore(s, next_sample, duration, T));
      if (!why.empty()) {
        out.push_back(origin + ":" + std::to_string(f.line) + ":" + std::to_string(f.column) + ": fault #" +
                      std::to_string(i + 1) + " (star_tracker_outage): " + why + " (and no gyro_bias_jump acts "
                      "before the outage's next sample): the outage would be flagged and change no estimate");
        continue;
      }
    }
    const double end = std::min(f.end, duration);  // the run's last tick takes no step
    // A fault from the run's end on is a run cut short of it (checkFaultsAgainstDuration); a longer one holds one.
    if (f.kind != FaultKind::StarTrackerOutage || f.start >= duration - tol || end - f.start > P + T) continue;
    bool acts = false;
    const double j0 = std::max(0.0, std::floor((f.start - p.star_tracker_latency) / P) - 1.0);
    for (double j = j0; !acts && j * P <= end + P; ++j) {  // a few samples: the window is at most P + T long
      const double taken = firstTickAtOrAfter(j * P, T) * T;
      const double delivered = firstTickAtOrAfter(j * P + p.star_tracker_latency, T) * T;
      const auto inside = [&](double t) { return t >= f.start - tol && t < end - tol; };
      // a sample taken in the outage is lost, which matters only if it would be delivered within the run (pass
      // 90: its one sample, 0.15 s late, fell due after the run's end); one due in it is dropped
      acts = (inside(taken) && delivered <= duration + tol) || inside(delivered);
    }
    if (acts) continue;
    out.push_back(origin + ":" + std::to_string(f.line) + ":" + std::to_string(f.column) + ": fault #" +
                  std::to_string(i + 1) + " (star_tracker_outage): [" + formatNumber(f.start) + ", " +
                  formatNumber(f.end) + ") s takes and delivers no star tracker sample (one every " +
                  formatNumber(P) + " s, sensors.star_tracker_rate; latency " + formatNumber(p.star_tracker_latency) +
                  " s): it would change nothing but its flag");
  }
  return out;
}

}  // namespace gimbalsim::firmware
