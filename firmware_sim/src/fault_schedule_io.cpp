#include "gimbalsim/firmware_sim/fault_schedule_io.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "gimbalsim/input/key_registry.hpp"

namespace gimbalsim::firmware {
namespace {

/// The parameter key of each kind (none: "").
const char* paramKey(FaultKind k) {
  switch (k) {
    case FaultKind::EncoderBias: return "bias";
    case FaultKind::EncoderNoise: return "sigma";
    case FaultKind::StatusDelay:
    case FaultKind::CommandDelay: return "ticks";
    case FaultKind::TorqueLimit: return "limit";
    case FaultKind::GyroBiasJump: return "bias";
    case FaultKind::TrackerBias: return "bias";
    case FaultKind::BearingWear: return "clearance";
    case FaultKind::FrictionRise: return "mu";
    default: return "";
  }
}


std::string place(const std::string& origin, const YAML::Mark& m) {
  return origin + ":" + std::to_string(m.line + 1) + ":" + std::to_string(m.column + 1);
}

class Reader {
 public:
  explicit Reader(std::string origin) : origin_(std::move(origin)) {}

  FaultSchedule read(const std::string& yaml) {
    FaultSchedule s;
    // The bounded reader of every input (one document, no aliases, bounded
    // size and depth): a second document ('---') is refused, not ignored.
    YAML::Node root;
    if (Problem why; !loadDocument(yaml, origin_, root, why)) {
      problems_.push_back(why.text);
      return s;
    }
    if (!root.IsMap()) {
      problems_.push_back(origin_ + ": a fault schedule must be a mapping with keys seed and faults");
      return s;
    }
    std::map<std::string, std::string> first;  // key -> where it was first given
    for (const auto& kv : root) {
      const std::string key = kv.first.Scalar();
      if (givenTwice(first, key, "", kv.first.Mark())) continue;
      if (key == "seed") {
        convert(kv.second, "", "seed", [&](const YAML::Node& n) {
          const int v = asInt(n);
          if (v < 0) throw ConvertError{"must be >= 0, got " + std::to_string(v)};
          s.seed = static_cast<std::uint64_t>(v);
        });
      } else if (key == "faults") {
        if (!kv.second.IsSequence()) {
          problems_.push_back(place(origin_, kv.second.Mark()) + ": key 'faults': must be a list of faults");
          continue;
        }
        if (kv.second.size() > static_cast<std::size_t>(kMaxFaults)) {
          problems_.push_back(place(origin_, kv.second.Mark()) + ": key 'faults': at most " +
                              std::to_string(kMaxFaults) + " faults (every tick evaluates each), got " +
                              std::to_string(kv.second.size()));
          continue;
        }
        int i = 0;
        for (const YAML::Node& e : kv.second) readFault(e, ++i, s.faults);
      } else {
        problems_.push_back(place(origin_, kv.first.Mark()) + ": unknown key '" + shownText(key) +
                            "' (a fault schedule has seed and faults; docs/bench.md \"Fault schedule\")");
      }
    }
    return s;
  }

  std::vector<std::string> problems_;

 private:
  /// A key given twice is a problem at its second place, as in a scene (yaml-cpp keeps one silently; pass 52:
  /// a second seed or start was taken without a word).
  bool givenTwice(std::map<std::string, std::string>& first, const std::string& key, const std::string& entry,
                  const YAML::Mark& m) {
    const auto [it, fresh] = first.try_emplace(key, place(origin_, m));
    if (!fresh) {
      problems_.push_back(place(origin_, m) + ": " + entry + "key '" + shownText(key) + "': given twice (first at " +
                          it->second + ")");
    }
    return !fresh;
  }

  template <class F>
  void convert(const YAML::Node& n, const std::string& entry, const std::string& key, F set) {
    try {
      set(n);
    } catch (const ConvertError& e) {
      problems_.push_back(place(origin_, n.Mark()) + ": " + entry + "key '" + shownText(key) + "': " + e.msg);
    }
  }

  void readFault(const YAML::Node& e, int index, std::vector<FaultSpec>& out) {
    const std::string where = place(origin_, e.Mark());
    std::string entry = "fault #" + std::to_string(index) + ": ";
    if (!e.IsMap()) {
      problems_.push_back(where + ": " + entry + "must be a mapping (type, start, ...)");
      return;
    }
    const std::size_t before = problems_.size();
    FaultSpec f;
    f.line = e.Mark().line + 1;
    f.column = e.Mark().column + 1;
    const YAML::Node type = e["type"];
    if (!type) {
      problems_.push_back(where + ": " + entry + "key 'type' is missing");
      return;
    }
    std::vector<std::string> names;
    for (int k = 0; k < kNumFaultKinds; ++k) names.push_back(faultTypeName(static_cast<FaultKind>(k)));
    bool typed = false;
    convert(type, entry, "type", [&](const YAML::Node& n) {
      f.kind = static_cast<FaultKind>(asChoice(n, names));
      typed = true;
    });
    if (!typed) return;
    entry = "fault #" + std::to_string(index) + " (" + faultTypeName(f.kind) + "): ";
    const std::string param = paramKey(f.kind);
    std::set<std::string> seen;
    std::map<std::string, std::string> first;  // key -> where it was first given
    for (const auto& kv : e) {
      const std::string key = kv.first.Scalar();
      seen.insert(key);
      if (givenTwice(first, key, entry, kv.first.Mark())) continue;
      const YAML::Node& n = kv.second;
      if (key == "type") continue;
      if (key == "axis" && (faultHasAxis(f.kind) || faultIsRamp(f.kind))) {
        convert(n, entry, key, [&](const YAML::Node& v) { f.axis = static_cast<int>(asChoice(v, {"azimuth", "elevation"})); });
        f.axis_line = n.Mark().line + 1, f.axis_column = n.Mark().column + 1;
      } else if (key == "start") {
        convert(n, entry, key, [&](const YAML::Node& v) {
          f.start = asNumber(v);
          if (!(f.start >= 0.0 && f.start <= kMaxFaultTime)) {
            throw ConvertError{"must be in [0, " + formatNumber(kMaxFaultTime) + "] s, got " + formatNumber(f.start)};
          }
        });
      } else if (key == "end") {
        convert(n, entry, key, [&](const YAML::Node& v) {
          f.end = asNumber(v);
          if (!(f.end >= 0.0 && f.end <= kMaxFaultTime)) {
            throw ConvertError{"must be in [0, " + formatNumber(kMaxFaultTime) + "] s, got " + formatNumber(f.end)};
          }
        });
      } else if (key == "probability" && !faultIsRamp(f.kind)) {
        convert(n, entry, key, [&](const YAML::Node& v) {
          f.probability = asNumber(v);
          if (!(f.probability > 0.0 && f.probability <= 1.0)) {
            throw ConvertError{"must be in (0, 1] (per tick), got " + formatNumber(f.probability)};
          }
        });
      } else if (!param.empty() && key == param) {
        convert(n, entry, key, [&](const YAML::Node& v) { readParam(f, v); });
        f.param_line = n.Mark().line + 1, f.param_column = n.Mark().column + 1;
      } else {
        std::string allowed = "type, start, end";
        if (faultHasAxis(f.kind) || faultIsRamp(f.kind)) allowed += ", axis";
        if (!faultIsRamp(f.kind)) allowed += ", probability";
        if (!param.empty()) allowed += ", " + param;
        problems_.push_back(place(origin_, kv.first.Mark()) + ": " + entry + "unknown key '" + shownText(key) + "' (" +
                            faultTypeName(f.kind) + " takes " + allowed + ")");
      }
    }
    if (faultHasAxis(f.kind) && !seen.count("axis")) {
      problems_.push_back(where + ": " + entry + "key 'axis' is missing (azimuth or elevation)");
    }
    if (!param.empty() && !seen.count(param)) {
      problems_.push_back(where + ": " + entry + "key '" + shownText(param) + "' is missing");
    }
    if (f.kind == FaultKind::BearingWear && !seen.count("end")) {
      problems_.push_back(where + ": " + entry + "key 'end' is missing (the wear grows over [start, end])");
    }
    if (faultIsRamp(f.kind) && !seen.count("end")) f.end = f.start;  // friction rise: a step
    if (seen.count("end") && problems_.size() == before) {
      const bool ok = faultIsRamp(f.kind) ? f.end >= f.start : f.end > f.start;
      if (!ok) {
        problems_.push_back(place(origin_, e["end"].Mark()) + ": " + entry + "key 'end': must be " +
                            (faultIsRamp(f.kind) ? ">= start" : "> start") + ", got " + formatNumber(f.end) +
                            " (start " + formatNumber(f.start) + ")");
      }
    }
    if (problems_.size() == before) out.push_back(f);
  }

  /// One parameter, within a range the plant and the controller honour (no
  /// value that overflows a sensor reading or a force to Inf).
  static void readParam(FaultSpec& f, const YAML::Node& v) {
    auto within = [](double x, double lo, double hi, const char* unit) {
      if (!(x >= lo && x <= hi)) {
        throw ConvertError{"must be in [" + formatNumber(lo) + ", " + formatNumber(hi) + "]" + unit + ", got " +
                           formatNumber(x)};
      }
      return x;
    };
    // (pass 79) a bias of 0 changes no reading: the fault would be flagged as injected and act on nothing
    auto nonzero = [](bool acts, const char* what) {
      if (!acts) throw ConvertError{std::string(what) + " adds nothing: the fault would act on nothing"};
    };
    switch (f.kind) {
      case FaultKind::EncoderBias:
        f.value = within(asNumber(v), -kMaxEncoderBias, kMaxEncoderBias, " rad");
        nonzero(f.value != 0.0, "a bias of 0");
        break;
      case FaultKind::EncoderNoise:
        f.value = asNumber(v);
        if (!(f.value > 0.0 && f.value <= kMaxEncoderBias)) {
          throw ConvertError{"must be in (0, " + formatNumber(kMaxEncoderBias) + "] rad, got " + formatNumber(f.value)};
        }
        break;
      case FaultKind::StatusDelay:
      case FaultKind::CommandDelay:
        f.ticks = asInt(v);
        if (f.ticks < 1 || f.ticks > kMaxFaultDelayTicks) {
          throw ConvertError{"must be in [1, " + std::to_string(kMaxFaultDelayTicks) + "] ticks, got " +
                             std::to_string(f.ticks)};
        }
        break;
      case FaultKind::TorqueLimit: f.value = within(asNumber(v), 0.0, kMaxFaultTorque, " N m"); break;
      case FaultKind::GyroBiasJump:
        f.vector = asVector<3>(v, "[x, y, z] in rad/s");
        for (int i = 0; i < 3; ++i) within(f.vector(i), -kMaxGyroBiasJump, kMaxGyroBiasJump, " rad/s (each axis)");
        nonzero(f.vector.any(), "a bias of 0 on every axis");
        break;
      case FaultKind::TrackerBias: {
        const Vec2 b = asVector<2>(v, "[u, v] in rad");
        for (int i = 0; i < 2; ++i) within(b(i), -kMaxTrackerBias, kMaxTrackerBias, " rad (each axis)");
        nonzero(b.any(), "a bias of 0 on both axes");
        f.vector << b, 0.0;
        break;
      }
      case FaultKind::BearingWear:
        f.value = asNumber(v);
        if (!(f.value > 0.0)) throw ConvertError{"must be > 0 m, got " + formatNumber(f.value)};
        break;
      case FaultKind::FrictionRise: f.value = within(asNumber(v), 0.0, kMaxFrictionMu, ""); break;
      default: break;
    }
  }

  // The ranges of the parameters (docs/bench.md "Fault schedule").
  static constexpr double kMaxFaultTime = 1e9;      ///< [s] start, end (firmware_sim --duration's bound)
  static constexpr double kMaxEncoderBias = 100.0;  ///< [rad] encoder bias and noise sigma
  static constexpr double kMaxFaultTorque = 1e6;    ///< [N m] torque limit
  static constexpr double kMaxGyroBiasJump = 1.0;   ///< [rad/s] per axis, as sensors.gyro_bias
  static constexpr double kMaxTrackerBias = 0.1;    ///< [rad] per axis, as sensors.tracker_bias
  static constexpr double kMaxFrictionMu = 10.0;    ///< [-] friction coefficient

  std::string origin_;
};

}  // namespace

FaultSchedule loadFaultScheduleText(const std::string& yaml, const std::string& origin) {
  Reader r(origin);
  FaultSchedule s = r.read(yaml);
  if (!r.problems_.empty()) throw FaultScheduleError(r.problems_);
  return s;
}

FaultSchedule loadFaultSchedule(const std::string& path) {
  std::string text;
  std::string why;
  if (!readFile(path, text, &why)) throw FaultScheduleError({path + ": cannot open fault schedule file: " + why});
  return loadFaultScheduleText(text, path);
}

int torqueLimitClipsNothingOn(const FaultSpec& f, const Vec2& limit_Nm) {
  for (int j = 0; j < 2 && f.kind == FaultKind::TorqueLimit; ++j) {
    if ((f.axis == j || f.axis < 0) && !(f.value < limit_Nm(j))) return j;
  }
  return -1;
}

std::vector<std::string> checkFaultsAgainstDuration(const FaultSchedule& s, double duration, double tick_period,
                                                     const std::string& origin) {
  std::vector<std::string> out;
  const double T = tick_period, tol = 1e-9 * tick_period;  // FaultClock::at's tick instants and tolerance
  for (std::size_t i = 0; i < s.faults.size(); ++i) {
    const FaultSpec& f = s.faults[i];
    if (faultIsRamp(f.kind) || !(T > 0.0)) continue;
    // FaultClock::at: active at tick k when start - tol <= k T < end - tol
    const double k = firstTickAtOrAfter(f.start, T);
    if (k * T < f.end - tol) continue;
    out.push_back(origin + ":" + std::to_string(f.line) + ":" + std::to_string(f.column) + ": fault #" +
                  std::to_string(i + 1) + " (" + faultTypeName(f.kind) + "): [" + formatNumber(f.start) + ", " +
                  formatNumber(f.end) + ") s holds no tick (one every " + formatNumber(T) + " s; tick " +
                  formatNumber(k) + " comes after its end): it would act in no tick");
  }
  if (!out.empty()) return out;
  // The tick from which a fault changes a step: its first; a ramp's next (it holds the scene's own value at its
  // first tick: a friction_rise from 0.199 s of a 0.2 s run was "active in 2 ticks" and changed none, pass 111).
  const auto acting_s = [&](const FaultSpec& f) {
    return T > 0.0 ? (firstTickAtOrAfter(f.start, T) + (faultIsRamp(f.kind) ? 1.0 : 0.0)) * T : f.start;
  };
  const auto first = std::min_element(s.faults.begin(), s.faults.end(), [&](const FaultSpec& a, const FaultSpec& b) {
    return acting_s(a) < acting_s(b);
  });
  // The run's last tick ends it: a fault from there on takes no step (a motor failure at the end was flagged as
  // injected and changed nothing, pass 84), and so does one whose first tick is that one (a start inside the
  // last period, pass 86).
  if (first == s.faults.end()) return {};
  if (acting_s(*first) < duration - tol) return {};
  const auto i = first - s.faults.begin() + 1;
  // a ramp whose first tick comes before the last: its next is (pass 112: one inside the last period said so too)
  const bool ramp = faultIsRamp(first->kind) && acting_s(*first) - T < duration - tol;
  const std::string when = first->start >= duration - tol
                               ? " s is at or after the run's end at " + formatNumber(duration) + " s"
                               : std::string(ramp ? " s: a ramp holds the scene's value at its first tick, and its "
                                                    "next is the run's last, at "
                                                  : " s: its first tick is the run's last, at ") +
                                     formatNumber(duration) + " s (one every " + formatNumber(T) +
                                     " s), which ends the run and takes no step";
  return {origin + ":" + std::to_string(first->line) + ":" + std::to_string(first->column) + ": fault #" +
          std::to_string(i) + " (" + faultTypeName(first->kind) + "), the first to start: key 'start': " +
          formatNumber(first->start) + when + ": every fault starts there or later, the schedule would act in no step"};
}

std::vector<std::string> checkFaultsAgainstScene(const FaultSchedule& s, const PlantScene& ps, const std::string& origin) {
  std::vector<std::string> out;
  const Model& m = ps.scene.model;
  int i = 0;
  for (const FaultSpec& f : s.faults) {
    ++i;
    // Each refusal at its place (file:line:column): the entry's, or its axis's or parameter's value.
    auto placeAt = [&](int line, int column) {
      return origin + ":" + std::to_string(line) + ":" + std::to_string(column) + ": fault #" + std::to_string(i) +
             " (" + faultTypeName(f.kind) + "): ";
    };
    const std::string at = placeAt(f.line, f.column);
    const std::string at_axis = f.axis_line > 0 ? placeAt(f.axis_line, f.axis_column) : at;
    const std::string at_param = f.param_line > 0 ? placeAt(f.param_line, f.param_column) : at;
    const bool tracker = f.kind == FaultKind::TrackerOutage || f.kind == FaultKind::TrackerBias ||
                         f.kind == FaultKind::TrackerDropout;
    if (tracker && !ps.sensors.antenna_sensors) {
      out.push_back(at + "the scene has no tracker to act on (scene key sensors.antenna is none)");
      continue;
    }
    // (pass 79) a limit at or above the motor's drops nothing: the fault would be flagged and act on nothing
    if (const int j = torqueLimitClipsNothingOn(f, ps.scene.run.torque_limit); j >= 0) {
      out.push_back(at_param + "key 'limit': " + formatNumber(f.value) + " N m is not below the " +
                    (j == 0 ? "azimuth" : "elevation") + " motor's limit (scene key torque.limit, " +
                    formatNumber(ps.scene.run.torque_limit(j)) + " N m): the limit would not drop");
    }
    if (!faultIsRamp(f.kind)) continue;
    if (f.axis >= 0 && m.jointKind(f.axis) == ClearanceKind::Ideal) {
      const std::string joint = "joint" + std::to_string(f.axis + 1);
      out.push_back(at_axis + "key 'axis': the " + (f.axis == 0 ? "azimuth" : "elevation") +
                    " joint is ideal (scene key structure." + joint + "): it has no bearing to act on");
      continue;
    }
    if (f.axis < 0 && !m.hasClearance()) {
      out.push_back(at + "needs a joint with clearance (scene key structure.joint1 or structure.joint2 = planar "
                         "or spatial)");
      continue;
    }
    // Checked against each bearing it acts on.
    for (int j = 0; j < 2; ++j) {
      if (!(f.axis == j || (f.axis < 0 && m.jointKind(j) != ClearanceKind::Ideal))) continue;
      const ContactParams& c = m.bearing[j];
      const std::string joint = "joint" + std::to_string(j + 1);
      if (f.kind == FaultKind::BearingWear && !(f.value > c.clearance && f.value < c.bearing_radius)) {
        out.push_back(at_param + "key 'clearance': must be above " + joint + "'s clearance " + formatNumber(c.clearance) +
                      " m and below " + joint + ".contact.bearing_radius " + formatNumber(c.bearing_radius) +
                      " m, got " + formatNumber(f.value));
      }
      // Worn, a spatial bearing must stay long enough for its model, as the scene's own clearance must.
      if (f.kind == FaultKind::BearingWear && m.jointKind(j) == ClearanceKind::Spatial &&
          !(c.bearing_length >= kSpatialMinLengthInClearances * f.value)) {
        out.push_back(at_param + "key 'clearance': a spatial bearing must be at least " +
                      formatNumber(kSpatialMinLengthInClearances) + " clearances long: " + joint +
                      ".contact.bearing_length " + formatNumber(c.bearing_length) + " m against " +
                      formatNumber(kSpatialMinLengthInClearances) + " x " +
                      formatNumber(f.value) + " m");
      }
      if (f.kind == FaultKind::FrictionRise && c.friction == FrictionLaw::None) {
        out.push_back(at + "needs a friction law on " + joint + " (scene key " + joint + ".friction.law is none)");
      } else if (f.kind == FaultKind::FrictionRise && f.value == c.mu) {  // (pass 79) a rise to where it is
        out.push_back(at_param + "key 'mu': " + formatNumber(f.value) + " is " + joint + "'s friction.mu already: " +
                      "the fault would change nothing");
      }
    }
  }
  return out;
}

}  // namespace gimbalsim::firmware
