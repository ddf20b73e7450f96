#include "gimbalsim/controllers/key_use.hpp"

#include <algorithm>
#include <map>

#include "gimbalsim/controllers/config.hpp"

namespace gimbalsim::controllers {

const std::vector<KeyReadRule>& controllerReadRules() {
  static const ReadingSetting kInertial{"pointing.mode", {"inertial"}};
  static const ReadingSetting kModel{"pointing.accel_feedforward", {"model"}};
  static const std::vector<KeyReadRule> kRules = {
      {"control.rate_filter_hz", {{{"control.rate_source", {"difference"}}}}},
      {"pointing.target", {{kInertial}}},
      {"pointing.fixed_direction", {{kInertial}, {{"pointing.target", {"fixed"}}}}},
      {"pointing.base_accel_filter_hz", {{kInertial}, {{"pointing.accel_feedforward", {"inertial"}}}}},
      {"gimbal.azimuth_inertia_cos2", {{{"pointing.accel_feedforward", {"profile", "inertial"}}}}},
      // the joint axes: the inertial mode's inverse kinematics, or the model feed-forward's plant
      {"gimbal.joint1_axis", {{kInertial, kModel}}},
      {"gimbal.joint2_axis", {{kInertial, kModel}}},
      // the boresight only by the inverse kinematics: the plant's dynamics (crba, rnea) never read it
      {"gimbal.boresight", {{kInertial}}},
      {"azimuth.aw_gain", {{{"control.anti_windup", {"back_calculation"}}}}},
      {"elevation.aw_gain", {{{"control.anti_windup", {"back_calculation"}}}}},
      {"plant.", {{kModel}}}};
  return kRules;
}

namespace {

const KeyReadRule* ruleOf(const std::string& key) {
  const auto& rules = controllerReadRules();
  const auto exact = std::find_if(rules.begin(), rules.end(), [&](const KeyReadRule& r) { return r.key == key; });
  if (exact != rules.end()) return &*exact;
  const std::string prefix = key.substr(0, key.find('.') + 1);
  const auto under = std::find_if(rules.begin(), rules.end(), [&](const KeyReadRule& r) { return r.key == prefix; });
  return under != rules.end() ? &*under : nullptr;
}

std::string joined(const std::vector<std::string>& words, const char* between) {
  std::string text;
  for (const std::string& w : words) text += (text.empty() ? "" : between) + w;
  return text;
}

using KeyValues = std::map<std::string, std::string>;

/// Every key of the configuration with its value as text (configValues), by key.
KeyValues valuesByKey(const ControllerConfig& c) {
  KeyValues value;
  for (const std::string& kv : configValues(c)) value[kv.substr(0, kv.find('='))] = kv.substr(kv.find('=') + 1);
  return value;
}

/// controllerKeyIdle on the configuration's values, read once by the caller for all its keys.
std::string keyIdle(KeyValues& value, const std::string& key, bool scene_has_antenna_sensor) {
  if (key.rfind("antenna.", 0) == 0) {  // tracker_fusion.cpp: the antenna's keys act where the loop closes there
    if (!scene_has_antenna_sensor) {
      return "the scene's sensors.antenna is none: no sensor on the antenna, the loop closes on the encoders";
    }
    if (key != "antenna.tracker" && value["antenna.tracker"] != "use") {
      return "the controller's antenna.tracker is ignore: it reads no antenna sensor";
    }
  }
  const KeyReadRule* rule = ruleOf(key);
  if (rule == nullptr) return "";
  for (const auto& condition : rule->conditions) {
    const bool holds = std::any_of(condition.begin(), condition.end(), [&](const ReadingSetting& s) {
      return std::find(s.values.begin(), s.values.end(), value[s.key]) != s.values.end();
    });
    if (holds) continue;
    std::vector<std::string> reads, has;
    for (const ReadingSetting& s : condition) {
      reads.push_back(s.key + " " + joined(s.values, " or "));
      has.push_back(s.key + " " + value[s.key]);
    }
    return "the controller reads it only with " + joined(reads, " or with ") + "; it has " + joined(has, ", ");
  }
  return "";
}

}  // namespace

std::string controllerKeyIdle(const ControllerConfig& c, const std::string& key, bool scene_has_antenna_sensor) {
  KeyValues value = valuesByKey(c);
  return keyIdle(value, key, scene_has_antenna_sensor);
}

std::string controllerValueRunsAsAnother(const ControllerConfig& c) {
  // (pass 99) inertial_reference.cpp: the joint law feeds forward the profile's acceleration whatever the value
  if (c.pointing_mode == PointingMode::Joint && c.accel_feedforward == AccelFeedForward::Inertial) {
    return "pointing.accel_feedforward inertial runs as profile with pointing.mode joint (the inertial "
           "feed-forward is the inertial mode's; the joint law takes the profile's joint acceleration)";
  }
  return "";
}

std::string idleControllerOverride(const char* flag, const std::vector<std::string>& overrides,
                                   const ControllerConfig& c, bool scene_has_antenna_sensor,
                                   const std::vector<std::pair<std::string, std::string>>& never_read) {
  KeyValues value = valuesByKey(c);
  const std::string runs_as = controllerValueRunsAsAnother(c);
  std::string deciding;  // the last override of a key that makes runs_as
  for (std::size_t k = 0; k < overrides.size(); ++k) {
    const std::string key = overrides[k].substr(0, overrides[k].find('='));
    const std::string named = std::string(flag) + " #" + std::to_string(k + 1) + " '" + overrides[k] + "'";
    std::string why = keyIdle(value, key, scene_has_antenna_sensor);
    for (const auto& [idle, because] : never_read) {
      if (why.empty() && key == idle) why = because;
    }
    if (!why.empty()) {
      return named + ": not read by these runs (" + why + "): the value would be recorded but never act";
    }
    if (key == "pointing.accel_feedforward" || key == "pointing.mode") deciding = named;
  }
  if (runs_as.empty()) return "";
  // (pass 104, 107) given in the file: named at its line there, not "the controller configuration"
  return (deciding.empty() ? c.runs_as_another.text : deciding + ": " + runs_as) +
         ": the value would be recorded but act as another";
}

}  // namespace gimbalsim::controllers
