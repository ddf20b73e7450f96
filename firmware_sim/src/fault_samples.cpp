// A star tracker outage (a fault's, or the scene key's) against the tracker's samples (attitude_sensors.hpp:
// sample j belongs to j P and is taken in the first tick at or after it, delivered in the first tick at or after
// t_s + latency), and whether anything but a perfect gyro could tell the estimate what it withholds.
#include <algorithm>
#include <cmath>

#include "gimbalsim/firmware_sim/fault_schedule_io.hpp"
#include "gimbalsim/input/value_format.hpp"

namespace gimbalsim::firmware {

bool gyroJumpActsBefore(const FaultSchedule& s, double t_before, double duration, double tick_period) {
  const double T = tick_period, tol = 1e-9 * tick_period;
  return std::any_of(s.faults.begin(), s.faults.end(), [&](const FaultSpec& g) {
    return g.kind == FaultKind::GyroBiasJump && g.start < t_before &&
           firstTickAtOrAfter(g.start, T) * T < duration - tol;
  });
}

double starSampleDeliveredFrom(const SensorParams& p, double t, double tick_period) {
  const double T = tick_period, P = 1.0 / p.star_tracker_rate;
  const double j = std::max(0.0, std::ceil((t - 1e-9 * T) / P));  // the first sample instant at or after t
  return firstTickAtOrAfter(j * P + p.star_tracker_latency, T) * T;
}

bool starOutageDropsASample(const SensorParams& p, double start, double end, bool end_inclusive, double duration,
                            double tick_period) {
  const double T = tick_period, tol = 1e-9 * tick_period, P = 1.0 / p.star_tracker_rate;
  const double last = std::min(end, duration);  // the run's last tick takes no step
  // a window longer than a period and a tick holds a take or a delivery (pass 87's judgement is for short ones)
  if (!(T > 0.0) || !(P > 0.0) || last - start > P + T) return true;
  const auto inside = [&](double t) {
    return t >= start - tol && (end_inclusive && end <= duration ? t <= end + tol : t < last - tol);
  };
  const double j0 = std::max(0.0, std::floor((start - p.star_tracker_latency) / P) - 1.0);
  for (double j = j0; j * P <= last + P; ++j) {  // a few samples
    const double taken = firstTickAtOrAfter(j * P, T) * T;
    const double delivered = firstTickAtOrAfter(j * P + p.star_tracker_latency, T) * T;
    // a sample taken in the outage is lost, which matters only if it would be delivered within the run (pass
    // 90: its one sample, 0.15 s late, fell due after the run's end); one due in it is dropped
    if ((inside(taken) && delivered <= duration + tol) || inside(delivered)) return true;
  }
  return false;
}

std::vector<std::string> checkFaultsAgainstSamples(const FaultSchedule& s, const PlantScene& ps, double duration,
                                                   double tick_period, const std::string& origin) {
  std::vector<std::string> out;
  const SensorParams& p = ps.sensors;
  const double T = tick_period, tol = 1e-9 * tick_period, P = 1.0 / p.star_tracker_rate;
  if (!(T > 0.0) || !(P > 0.0)) return out;
  for (std::size_t i = 0; i < s.faults.size(); ++i) {
    const FaultSpec& f = s.faults[i];
    if (f.kind != FaultKind::StarTrackerOutage) continue;
    const std::string at = origin + ":" + std::to_string(f.line) + ":" + std::to_string(f.column) + ": fault #" +
                           std::to_string(i + 1) + " (star_tracker_outage): ";
    // (pass 89) on a fixed base with perfect sensors the estimate is exact without a sample, unless a gyro bias
    // jump acts by the first sample after the outage (passes 90-93: one after it, or after the run's end, let the
    // outage through)
    const double next_sample = starSampleDeliveredFrom(p, f.end, T);
    if (const std::string why = starTrackerRedundant(p, ps.scene.model.floating_base,
                                                     gyroJumpActsBefore(s, next_sample + T, duration, T));
        !why.empty()) {
      out.push_back(at + why + " (and no gyro_bias_jump acts by the outage's next sample): the outage would be "
                               "flagged and change no estimate");
      continue;
    }
    // (pass 87) an outage between two 10 Hz samples dropped none: only its flag changed, recorded as injected.
    // A fault from the run's end on is a run cut short of it (checkFaultsAgainstDuration).
    if (f.start >= duration - tol || starOutageDropsASample(p, f.start, f.end, false, duration, T)) continue;
    out.push_back(at + starOutageHoldsNoSample(p, f.start, f.end, false));
  }
  return out;
}

std::string starOutageHoldsNoSample(const SensorParams& p, double start, double end, bool end_inclusive) {
  return "[" + formatNumber(start) + ", " + formatNumber(end) + (end_inclusive ? "]" : ")") +
         " s takes and delivers no star tracker sample (one every " + formatNumber(1.0 / p.star_tracker_rate) +
         " s, sensors.star_tracker_rate; latency " + formatNumber(p.star_tracker_latency) +
         " s): it would change nothing but its flag";
}

}  // namespace gimbalsim::firmware
