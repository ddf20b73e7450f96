#include "gimbalsim/firmware_sim/firmware.hpp"

#include <cmath>
#include <sstream>

#include "gimbalsim/input/key_registry.hpp"

namespace gimbalsim::firmware {

const char* describe(Rejection r) {
  switch (r) {
    case Rejection::None: return "accepted";
    case Rejection::NonFinite: return "NaN or Inf torque";
    case Rejection::OutOfRange: return "torque beyond the sanity range";
    case Rejection::UnknownMode: return "unknown mode";
    case Rejection::StaleSeq: return "stale or duplicate seq";
    case Rejection::FutureStatus: return "answers a status not yet published";
    case Rejection::Undecodable: return "undecodable bytes (not a gimbal_command_t)";
    case Rejection::WrongSource: return "from another source than the bound controller";
  }
  return "?";
}

Rejection commonestRejection(const Counters& before, const Counters& now) noexcept {
  if (now.rejected - before.rejected <= 0) return Rejection::None;
  int most = 0;
  for (int i = 1; i < kNumRejections; ++i) {
    if (now.by_reason[i] - before.by_reason[i] > now.by_reason[most] - before.by_reason[most]) most = i;
  }
  return static_cast<Rejection>(most);
}

ConfigCheck checkConfig(const Scene& sc, const Config& c) {
  using Setting = ConfigCheck::Setting;
  ConfigCheck out;
  std::ostringstream err;
  auto refuse = [&](Setting s) {
    out.wrong = s;
    out.message = err.str();
    return out;
  };
  const double h = sc.model.integrator.step;
  if (!(c.control_period > 0.0) || !std::isfinite(c.control_period)) {
    err << "control period must be > 0 s, got " << c.control_period;
    return refuse(Setting::ControlPeriod);
  }
  if (!isWholeMultiple(c.control_period, h)) {
    // Numbers in their shortest round-trip text; no flag named: a rate, a period key or a sweep's value gave it.
    err << "control period " << formatNumber(c.control_period) << " s is not a whole multiple of sim.step = "
        << formatNumber(h) << " s (the plant steps sim.step at a time inside each tick): the period must be "
           "k * sim.step, or sim.step period / k";
    return refuse(Setting::ControlPeriod);
  }
  if (!(c.watchdog_timeout > 0.0)) {
    err << "watchdog timeout must be > 0 s, got " << c.watchdog_timeout;
    return refuse(Setting::WatchdogTimeout);
  }
  if (!(c.torque_sanity_factor >= 1.0)) {
    err << "torque sanity factor must be >= 1 (commands above factor * torque.limit are rejected), got "
        << c.torque_sanity_factor;
    return refuse(Setting::TorqueSanityFactor);
  }
  for (int i = 0; i < 2; ++i) {
    if (!std::isfinite(c.safe_torque(i)) || std::fabs(c.safe_torque(i)) > sc.run.torque_limit(i)) {
      err << "safe torque " << c.safe_torque(i) << " N m on axis " << i + 1
          << " must be finite and within torque.limit = " << sc.run.torque_limit(i) << " N m";
      return refuse(Setting::SafeTorque);
    }
  }
  out.steps_per_tick = static_cast<int>(std::round(c.control_period / h));
  return out;
}

}  // namespace gimbalsim::firmware
