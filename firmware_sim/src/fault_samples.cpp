// A window of a sampled sensor (a star tracker or boresight tracker outage, a tracker bias or dropout: a fault's,
// or the scene key's) against its samples (sample_schedule.hpp: sample j belongs to j P and is taken in the
// first tick at or after it, delivered in the first tick at or after t_s + latency), and whether anything but a
// perfect gyro could tell the estimate what a star tracker outage withholds.
#include <algorithm>
#include <cmath>
#include <optional>

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

SampledSensor starTrackerSampling(const SensorParams& p) {
  return {"star tracker", "sensors.star_tracker", p.star_tracker_rate, p.star_tracker_latency};
}

SampledSensor boresightTrackerSampling(const SensorParams& p) {
  return {"boresight tracker", "sensors.tracker", p.tracker_rate, p.tracker_latency};
}

bool windowHoldsASample(const SampledSensor& s, WindowActsOn acts, double start, double end, bool end_inclusive,
                        double duration, double tick_period, bool last_tick_acts) {
  const double T = tick_period, tol = 1e-9 * tick_period, P = 1.0 / s.rate;
  const double last = std::min(end, duration);
  const double acting = last_tick_acts ? duration : duration - T;  // the last delivery that can act
  // a window longer than a period and a tick holds a take or a delivery (pass 87's judgement is for short ones)
  if (!(T > 0.0) || !(P > 0.0) || last - start > P + T) return true;
  // (pass 116) a window past the run's end holds its last tick's sample too: closed_loop records what it moves
  const auto inside = [&](double t) { return t >= start - tol && (end_inclusive ? t <= end + tol : t < end - tol); };
  const bool takes = acts != WindowActsOn::Deliveries, deliveries = acts != WindowActsOn::Takes;
  const double j0 = std::max(0.0, std::floor((start - s.latency) / P) - 1.0);
  for (double j = j0; j * P <= last + P; ++j) {  // a few samples
    const double taken = firstTickAtOrAfter(j * P, T) * T;
    const double delivered = firstTickAtOrAfter(j * P + s.latency, T) * T;
    // a sample taken in the window matters only if it would be delivered within the run (pass 90: its one
    // sample, 0.15 s late, fell due after the run's end); one due in it, if deliveries are what it drops
    if (delivered <= acting + tol && ((takes && inside(taken)) || (deliveries && inside(delivered)))) return true;
  }
  return false;
}

bool outagesLoseEverySample(const SampledSensor& s, const std::vector<OutageWindow>& outages, double duration,
                            double tick_period) {
  const double T = tick_period, tol = 1e-9 * tick_period, P = 1.0 / s.rate;
  const bool any = std::any_of(outages.begin(), outages.end(), [](const OutageWindow& w) { return w.end > w.start; });
  if (!(T > 0.0) || !(P > 0.0) || !any || duration / P > 1e6) return false;
  const auto in_outage = [&](double t) {  // a fault's [start, end) as FaultClock::at reads it
    return std::any_of(outages.begin(), outages.end(), [&](const OutageWindow& w) {
      return w.end > w.start && t >= w.start - tol && (w.end_inclusive ? t <= w.end + tol : t < w.end - tol);
    });
  };
  for (double j = 0.0; j * P < duration; ++j) {
    const double taken = firstTickAtOrAfter(j * P, T) * T;
    const double delivered = firstTickAtOrAfter(j * P + s.latency, T) * T;
    if (delivered < duration - tol && !in_outage(taken) && !in_outage(delivered)) return false;  // this one acts
  }
  return true;
}

std::string windowHoldsNoSample(const SampledSensor& s, WindowActsOn acts, double start, double end,
                                bool end_inclusive) {
  const char* what = acts == WindowActsOn::Both ? " s takes and delivers no " : acts == WindowActsOn::Takes
                                                                                   ? " s takes no "
                                                                                   : " s has no delivery of a ";
  return "[" + formatNumber(start) + ", " + formatNumber(end) + (end_inclusive ? "]" : ")") + what + s.name +
         " sample (one every " + formatNumber(1.0 / s.rate) + " s, " + s.rate_key + "_rate; latency " +
         formatNumber(s.latency) + " s): it would change nothing but its flag";
}

namespace {

/// A fault kind whose window acts only through a sampled sensor's samples: the sensor (the star tracker's, else
/// the boresight tracker's) and what of its samples the window acts on.
struct SampledWindow {
  bool star;
  WindowActsOn acts;
};

/// (pass 97) an outage loses takes and deliveries, a bias biases takes, a dropout loses deliveries.
std::optional<SampledWindow> sampledWindowOf(FaultKind kind) {
  switch (kind) {
    case FaultKind::StarTrackerOutage: return SampledWindow{true, WindowActsOn::Both};
    case FaultKind::TrackerOutage: return SampledWindow{false, WindowActsOn::Both};
    case FaultKind::TrackerBias: return SampledWindow{false, WindowActsOn::Takes};
    case FaultKind::TrackerDropout: return SampledWindow{false, WindowActsOn::Deliveries};
    default: return std::nullopt;
  }
}

}  // namespace

std::vector<std::string> checkFaultsAgainstSamples(const FaultSchedule& s, const PlantScene& ps, double duration,
                                                   double tick_period, const std::string& origin,
                                                   bool last_tick_acts) {
  std::vector<std::string> out;
  const SensorParams& p = ps.sensors;
  const double T = tick_period, tol = 1e-9 * tick_period;
  if (!(T > 0.0)) return out;
  for (std::size_t i = 0; i < s.faults.size(); ++i) {
    const FaultSpec& f = s.faults[i];
    // (pass 97) the boresight tracker's window faults between two of its samples acted on none, as the star
    // tracker's did (pass 87)
    const std::optional<SampledWindow> window = sampledWindowOf(f.kind);
    if (!window || !(window->star || p.antenna_sensors)) continue;  // a tracker's without one: checkFaultsAgainstScene
    const bool star = window->star;
    const WindowActsOn acts = window->acts;
    const std::string at = origin + ":" + std::to_string(f.line) + ":" + std::to_string(f.column) + ": fault #" +
                           std::to_string(i + 1) + " (" + faultTypeName(f.kind) + "): ";
    // (pass 89) on a fixed base with perfect sensors the estimate is exact without a sample, unless a gyro bias
    // jump acts by the first sample after the outage (passes 90-93: one after it, or after the run's end, let the
    // outage through)
    if (star) {
      const double next_sample = starSampleDeliveredFrom(p, f.end, T);
      if (const std::string why = starTrackerRedundant(p, ps.scene.model.floating_base,
                                                       gyroJumpActsBefore(s, next_sample + T, duration, T));
          !why.empty()) {
        out.push_back(at + why + " (and no gyro_bias_jump acts by the outage's next sample): the outage would be "
                                 "flagged and change no estimate");
        continue;
      }
    }
    // (pass 87) an outage between two 10 Hz samples dropped none: only its flag changed, recorded as injected.
    // A fault from the run's end on is a run cut short of it (checkFaultsAgainstDuration).
    const SampledSensor sensor = star ? starTrackerSampling(p) : boresightTrackerSampling(p);
    if (f.start >= duration - tol ||
        windowHoldsASample(sensor, acts, f.start, f.end, false, duration, T, last_tick_acts)) {
      continue;
    }
    out.push_back(at + windowHoldsNoSample(sensor, acts, f.start, f.end, false));
  }
  return out;
}

}  // namespace gimbalsim::firmware
