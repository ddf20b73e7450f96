#include "gimbalsim/controllers/config.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

namespace gimbalsim::controllers {
namespace {

// A key binds to one field of ControllerConfig: a number, a pair of numbers
// (azimuth, elevation) or an enumeration given by name.
struct Key {
  std::string key;
  const char* type;
  const char* unit;
  const char* help;
  double ControllerConfig::*num = nullptr;
  double TargetProfile::*pnum = nullptr;
  Vec2 TargetProfile::*pvec = nullptr;
  int axis = -1;                     ///< 0 azimuth, 1 elevation: gain is a field of axis[axis]
  double AxisGains::*gain = nullptr;
  bool strict = false;               ///< refuse x <= 0 (else refuse x < 0); vec2 keys: no bound
};

struct Fail {
  std::string msg;
};

double number(const YAML::Node& n) {
  double x = 0.0;
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, x)) {
    throw Fail{"expected a number" + (n.IsScalar() ? ", got '" + n.Scalar() + "'" : std::string())};
  }
  if (!std::isfinite(x)) throw Fail{"must be finite, got '" + n.Scalar() + "'"};
  return x;
}

Vec2 pair(const YAML::Node& n) {
  if (!n.IsSequence() || n.size() != 2) throw Fail{"expected [azimuth, elevation]"};
  return {number(n[0]), number(n[1])};
}

const std::vector<Key>& keys() {
  static const std::vector<Key> k = [] {
    std::vector<Key> v = {
        {.key = "control.period", .type = "number", .unit = "s", .help = "control period Ts",
         .num = &ControllerConfig::period, .strict = true},
        {.key = "control.anti_windup", .type = "none|clamping|back_calculation", .unit = "",
         .help = "integrator anti-windup"},
        {.key = "control.rate_source", .type = "status|difference", .unit = "",
         .help = "rate in the derivative term: the status rates, or the filtered difference of the encoder angles"},
        {.key = "control.rate_filter_hz", .type = "number", .unit = "Hz",
         .help = "low-pass cutoff of the differenced rate (< 1/(2 Ts))", .num = &ControllerConfig::rate_filter_hz,
         .strict = true},
        {.key = "control.approach_margin", .type = "number", .unit = "-",
         .help = "large-error approach: closing rate <= sqrt(2 a |e|), a = margin torque_limit / inertia (0: plain PD)",
         .num = &ControllerConfig::approach_margin},
        {.key = "profile.start", .type = "vec2", .unit = "rad", .help = "azimuth, elevation before the slew",
         .pvec = &TargetProfile::start},
        {.key = "profile.slew_start", .type = "number", .unit = "s", .help = "time the slew begins",
         .pnum = &TargetProfile::slew_start},
        {.key = "profile.slew_target", .type = "vec2", .unit = "rad", .help = "azimuth, elevation at the slew's end",
         .pvec = &TargetProfile::slew_target},
        {.key = "profile.slew_time", .type = "number", .unit = "s", .help = "minimum-jerk slew duration",
         .pnum = &TargetProfile::slew_time, .strict = true},
        {.key = "profile.hold_time", .type = "number", .unit = "s", .help = "hold at the slew target",
         .pnum = &TargetProfile::hold_time},
        {.key = "profile.track_rate", .type = "vec2", .unit = "rad/s", .help = "pass rate r of the tracked target",
         .pvec = &TargetProfile::track_rate},
        {.key = "profile.track_ramp_time", .type = "number", .unit = "s", .help = "pass rate ramp-in time constant T_r",
         .pnum = &TargetProfile::track_ramp_time, .strict = true},
        {.key = "profile.track_amplitude", .type = "vec2", .unit = "rad", .help = "nutation amplitude A",
         .pvec = &TargetProfile::track_amplitude},
        {.key = "profile.track_period", .type = "vec2", .unit = "s", .help = "nutation period P (each > 0)",
         .pvec = &TargetProfile::track_period},
    };
    struct G {
      const char *name, *unit, *help;
      double AxisGains::*field;
      bool strict;
    };
    const G gains[] = {
        {"kp", "N m/rad", "proportional gain", &AxisGains::kp, false},
        {"ki", "N m/(rad s)", "integral gain", &AxisGains::ki, false},
        {"kd", "N m s/rad", "derivative gain", &AxisGains::kd, false},
        {"inertia", "kg m^2", "acceleration feed-forward inertia estimate (0: none)", &AxisGains::inertia, false},
        {"torque_limit", "N m", "command limit", &AxisGains::torque_limit, true},
        {"aw_gain", "1/s", "back-calculation anti-windup gain 1/T_t", &AxisGains::aw_gain, false},
    };
    const char* axes[2] = {"azimuth", "elevation"};
    for (int a = 0; a < 2; ++a) {
      for (const G& g : gains) {
        v.push_back({.key = std::string(axes[a]) + "." + g.name, .type = "number", .unit = g.unit, .help = g.help,
                     .axis = a, .gain = g.field, .strict = g.strict});
      }
    }
    return v;
  }();
  return k;
}

template <class E>
E named(const YAML::Node& n, std::initializer_list<std::pair<const char*, E>> names) {
  std::string allowed;
  for (const auto& [s, e] : names) {
    if (n.IsScalar() && n.Scalar() == s) return e;
    allowed += (allowed.empty() ? "" : " | ") + std::string(s);
  }
  throw Fail{"expected one of " + allowed + (n.IsScalar() ? ", got '" + n.Scalar() + "'" : std::string())};
}

void apply(const Key& k, const YAML::Node& n, ControllerConfig& c) {
  const std::string& key = k.key;
  if (key == "control.anti_windup") {
    c.anti_windup = named<AntiWindup>(n, {{"none", AntiWindup::None},
                                          {"clamping", AntiWindup::Clamping},
                                          {"back_calculation", AntiWindup::BackCalculation}});
    return;
  }
  if (key == "control.rate_source") {
    c.rate_source = named<RateSource>(n, {{"status", RateSource::Status}, {"difference", RateSource::Difference}});
    return;
  }
  if (k.pvec) {
    c.profile.*k.pvec = pair(n);
    return;
  }
  const double x = number(n);
  if (k.strict ? !(x > 0.0) : !(x >= 0.0)) {
    std::ostringstream os;
    os << "must be " << (k.strict ? "> 0" : ">= 0") << ", got " << x;
    throw Fail{os.str()};
  }
  if (k.num) c.*k.num = x;
  if (k.pnum) c.profile.*k.pnum = x;
  if (k.gain) c.axis[k.axis].*k.gain = x;
}

const Key* find(const std::string& key) {
  for (const Key& k : keys()) {
    if (key == k.key) return &k;
  }
  return nullptr;
}

std::string place(const std::string& origin, const YAML::Mark& mk) {
  if (mk.line < 0) return origin;
  return origin + ":" + std::to_string(mk.line + 1) + ":" + std::to_string(mk.column + 1);
}

/// Collects leaf values of nested sections as "a.b" -> (node, place).
void leaves(const YAML::Node& n, const std::string& prefix, const std::string& origin,
            std::map<std::string, std::pair<YAML::Node, std::string>>& out) {
  for (const auto& kv : n) {
    const std::string full = (prefix.empty() ? "" : prefix + ".") + kv.first.Scalar();
    if (kv.second.IsMap()) {
      leaves(kv.second, full, origin, out);
    } else {
      out[full] = {kv.second, place(origin, kv.first.Mark())};
    }
  }
}

}  // namespace

std::vector<KeyInfo> controllerKeys() {
  std::vector<KeyInfo> out;
  for (const Key& k : keys()) out.push_back({k.key, k.type, k.unit, k.help});
  return out;
}

std::vector<std::string> configValues(const ControllerConfig& c) {
  auto num = [](double x) {  // shortest of 15..17 digits that reads back exactly
    char b[32];
    for (int digits = 15; digits <= 17; ++digits) {
      std::snprintf(b, sizeof b, "%.*g", digits, x);
      if (std::strtod(b, nullptr) == x) break;
    }
    return std::string(b);
  };
  std::vector<std::string> out;
  for (const Key& k : keys()) {
    std::string v;
    if (k.key == "control.anti_windup") {
      v = c.anti_windup == AntiWindup::None ? "none" : c.anti_windup == AntiWindup::Clamping ? "clamping" : "back_calculation";
    } else if (k.key == "control.rate_source") {
      v = c.rate_source == RateSource::Status ? "status" : "difference";
    } else if (k.pvec) {
      const Vec2& x = c.profile.*k.pvec;
      v = "[" + num(x(0)) + ", " + num(x(1)) + "]";
    } else if (k.num) {
      v = num(c.*k.num);
    } else if (k.pnum) {
      v = num(c.profile.*k.pnum);
    } else {
      v = num(c.axis[k.axis].*k.gain);
    }
    out.push_back(k.key + "=" + v);
  }
  return out;
}

ControllerConfig loadControllerConfigText(const std::string& yaml, const std::string& origin,
                                          const std::vector<std::string>& overrides) {
  std::vector<std::string> problems;
  std::map<std::string, std::pair<YAML::Node, std::string>> given;
  try {
    const YAML::Node root = YAML::Load(yaml);
    if (root.IsMap()) {
      leaves(root, "", origin, given);
    } else if (root.IsDefined() && !root.IsNull()) {
      throw ConfigError({origin + ": a controller configuration must be a mapping of sections"});
    }
  } catch (const YAML::Exception& e) {
    throw ConfigError({place(origin, e.mark) + ": not valid YAML: " + e.msg});
  }
  for (size_t i = 0; i < overrides.size(); ++i) {
    const std::string& o = overrides[i];
    const std::string where = "--set #" + std::to_string(i + 1) + " '" + o + "'";
    const auto eq = o.find('=');
    if (eq == std::string::npos || eq == 0) {
      problems.push_back(where + ": expected key=value");
      continue;
    }
    try {
      given[o.substr(0, eq)] = {YAML::Load(o.substr(eq + 1)), where};
    } catch (const YAML::Exception& e) {
      problems.push_back(where + ": value is not valid: " + e.msg);
    }
  }
  ControllerConfig c;
  for (const auto& [key, value] : given) {
    const Key* k = find(key);
    if (!k) {
      problems.push_back(value.second + ": unknown key '" + key + "' (see controllers/README.md)");
      continue;
    }
    try {
      apply(*k, value.first, c);
    } catch (const Fail& f) {
      problems.push_back(value.second + ": key '" + key + "': " + f.msg);
    } catch (const YAML::Exception& e) {
      problems.push_back(value.second + ": key '" + key + "': " + e.msg);
    }
  }
  // Checks across keys, named by the key that is given (or its default).
  auto at = [&](const std::string& key) {
    auto it = given.find(key);
    return (it == given.end() ? origin + ": (default of " + key + ")" : it->second.second) + ": key '" + key + "': ";
  };
  if (problems.empty()) {
    if (!(c.rate_filter_hz < 0.5 / c.period)) {
      problems.push_back(at("control.rate_filter_hz") + "must be below the Nyquist frequency 1/(2 control.period)");
    }
    for (int i = 0; i < 2; ++i) {
      if (!(c.profile.track_period(i) > 0.0)) problems.push_back(at("profile.track_period") + "must be > 0");
    }
  }
  if (!problems.empty()) throw ConfigError(problems);
  return c;
}

ControllerConfig loadControllerConfig(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path);
  if (!in) throw ConfigError({path + ": cannot open controller configuration file"});
  std::stringstream ss;
  ss << in.rdbuf();
  return loadControllerConfigText(ss.str(), path, overrides);
}

}  // namespace gimbalsim::controllers
