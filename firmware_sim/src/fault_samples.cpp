// A star tracker outage in the fault schedule against the tracker's samples
// (attitude_sensors.hpp: sample j belongs to j P and is taken in the first tick
// at or after it, delivered in the first tick at or after t_s + latency).
#include <algorithm>
#include <cmath>

#include "gimbalsim/firmware_sim/fault_schedule_io.hpp"
#include "gimbalsim/input/value_format.hpp"

namespace gimbalsim::firmware {

// (pass 87) an outage between two 10 Hz samples dropped none: only its flag changed, recorded as injected.
std::vector<std::string> checkFaultsAgainstSamples(const FaultSchedule& s, const SensorParams& p, double duration,
                                                   double tick_period, const std::string& origin) {
  std::vector<std::string> out;
  const double T = tick_period, tol = 1e-9 * tick_period, P = 1.0 / p.star_tracker_rate;
  if (!(T > 0.0) || !(P > 0.0)) return out;
  for (std::size_t i = 0; i < s.faults.size(); ++i) {
    const FaultSpec& f = s.faults[i];
    const double end = std::min(f.end, duration);  // the run's last tick takes no step
    // A fault from the run's end on is a run cut short of it (checkFaultsAgainstDuration); a longer one holds one.
    if (f.kind != FaultKind::StarTrackerOutage || f.start >= duration - tol || end - f.start > P + T) continue;
    bool acts = false;
    const double j0 = std::max(0.0, std::floor((f.start - p.star_tracker_latency) / P) - 1.0);
    for (double j = j0; !acts && j * P <= end + P; ++j) {  // a few samples: the window is at most P + T long
      const double taken = firstTickAtOrAfter(j * P, T) * T;
      const double delivered = firstTickAtOrAfter(j * P + p.star_tracker_latency, T) * T;
      for (const double t : {taken, delivered}) {
        acts = acts || (t >= f.start - tol && t < end - tol);
      }
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
