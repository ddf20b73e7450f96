#include "gimbalsim/controllers/config.hpp"

#include "gimbalsim/pointing/profile_keys.hpp"

namespace gimbalsim::controllers {
namespace {

/// The gains and limits of one axis (azimuth.*, elevation.*).
std::vector<Key<AxisGains>> gainKeys() {
  using K = Keys<AxisGains>;
  return {
      K::number("kp", "N m/rad", "proportional gain", field(&AxisGains::kp), atLeast(0)),
      K::number("ki", "N m/(rad s)", "integral gain", field(&AxisGains::ki), atLeast(0)),
      K::number("kd", "N m s/rad", "derivative gain", field(&AxisGains::kd), atLeast(0)),
      K::number("inertia", "kg m^2", "acceleration feed-forward inertia estimate (0: none)",
                field(&AxisGains::inertia), atLeast(0)),
      K::number("torque_limit", "N m", "command limit", field(&AxisGains::torque_limit), greater(0)),
      K::number("aw_gain", "1/s", "back-calculation anti-windup gain 1/T_t", field(&AxisGains::aw_gain), atLeast(0)),
  };
}

std::vector<Key<ControllerConfig>> keys() {
  using K = Keys<ControllerConfig>;
  std::vector<Key<ControllerConfig>> v = {
      K::number("control.period", "s", "control period Ts; profile time of status k is k Ts",
                field(&ControllerConfig::period), greater(0)),
      K::choice<AntiWindup>("control.anti_windup", "integrator anti-windup", field(&ControllerConfig::anti_windup),
                            {{"none", AntiWindup::None},
                             {"clamping", AntiWindup::Clamping},
                             {"back_calculation", AntiWindup::BackCalculation}}),
      K::choice<RateSource>(
          "control.rate_source",
          "rate in the derivative term: the status rates, or the filtered difference of the encoder angles",
          field(&ControllerConfig::rate_source), {{"status", RateSource::Status}, {"difference", RateSource::Difference}}),
      K::number("control.rate_filter_hz", "Hz", "low-pass cutoff of the differenced rate, < 1/(2 control.period)",
                field(&ControllerConfig::rate_filter_hz), greater(0)),
      K::number("control.approach_margin", "-",
                "large-error approach: closing rate <= sqrt(2 a |e|), a = margin torque_limit / inertia (0: plain PD)",
                field(&ControllerConfig::approach_margin), atLeast(0)),
  };
  embed(v, "profile.", pointing::profileKeys().keys, [](auto& c) -> auto& { return c.profile; });
  embed(v, "azimuth.", gainKeys(), [](auto& c) -> auto& { return c.axis[0]; });
  embed(v, "elevation.", gainKeys(), [](auto& c) -> auto& { return c.axis[1]; });
  return v;
}

/// Checks across keys (every key has passed its own check).
void validate(const ControllerConfig& c, Given& g) {
  if (!(c.rate_filter_hz < 0.5 / c.period)) {
    g.refuse("control.rate_filter_hz", "must be below the Nyquist frequency 1/(2 control.period)");
  }
}

}  // namespace

const KeyTable<ControllerConfig>& controllerTable() {
  static const KeyTable<ControllerConfig> table{
      {"a controller configuration", "controller configuration file", "controllers/README.md", ""}, keys(), validate};
  return table;
}

std::vector<KeyInfo> controllerKeys() { return controllerTable().info(); }

std::vector<std::string> configValues(const ControllerConfig& c) { return controllerTable().values(c); }

ControllerConfig loadControllerConfigText(const std::string& yaml, const std::string& origin,
                                          const std::vector<std::string>& overrides) {
  return loadKeys<ConfigError>(controllerTable(), yaml, origin, overrides);
}

ControllerConfig loadControllerConfig(const std::string& path, const std::vector<std::string>& overrides) {
  std::string text;
  if (!readFile(path, text)) throw ConfigError({path + ": cannot open controller configuration file"});
  return loadControllerConfigText(text, path, overrides);
}

}  // namespace gimbalsim::controllers
