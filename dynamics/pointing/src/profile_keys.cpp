#include "gimbalsim/pointing/profile_keys.hpp"

#include <yaml-cpp/yaml.h>

#include "gimbalsim/input/input_error.hpp"

namespace gimbalsim::pointing {
namespace {

using P = TargetProfile;

const Check kAngle = interval('[', -1e3, 1e3, ']');    // [rad]
const Check kTime = interval('[', 0.0, 1e9, ']');      // [s] a start or a hold
// [s] a slew or a ramp: a minimum-jerk slew's jerk goes as 1/T^3, so a
// 1e-300 s slew overflowed to NaN torques; 1 us keeps it finite.
const Check kDuration = interval('[', 1e-6, 1e9, ']');

/// A pair (azimuth, elevation), refused as such when malformed.
template <class F>
Key<P> azEl(std::string key, std::string unit, std::string meaning, F f, const Check& check = {}) {
  return Keys<P>::vector<2>(std::move(key), std::move(unit), std::move(meaning), f, check, "[azimuth, elevation]");
}

/// The profile keys as a controller configuration names them, reading only its `profile:` section.
const KeyTable<P>& profileSection() {
  static const KeyTable<P> table = [] {
    KeyTable<P> t{{"a controller configuration", "profile file", "`pointing_controller --keys`, docs/controller_keys.md", "profile"},
                  {},
                  profileKeys().validate, {}, {}};
    embed(t.keys, "profile.", profileKeys().keys, [](auto& p) -> auto& { return p; });
    return t;
  }();
  return table;
}

}  // namespace

const KeyTable<P>& profileKeys() {
  using K = Keys<P>;
  static const KeyTable<P> table{
      {"a target profile", "profile file", "`pointing_controller --keys`, docs/controller_keys.md", ""},
      {
          // Ranges whose products with the law's gains (kp <= 1e9 N m/rad) and
          // the nutation's (A (2 pi / P)^2) stay finite: 1e300 rad gave NaN torques.
          azEl("start", "rad", "azimuth, elevation before the slew", field(&P::start), kAngle),
          K::number("slew_start", "s", "time the slew begins", field(&P::slew_start), kTime),
          azEl("slew_target", "rad", "azimuth, elevation at the slew's end", field(&P::slew_target), kAngle),
          K::number("slew_time", "s", "minimum-jerk slew duration", field(&P::slew_time), kDuration),
          K::number("hold_time", "s", "hold at the slew target", field(&P::hold_time), kTime),
          azEl("track_rate", "rad/s", "pass rate r of the tracked target", field(&P::track_rate),
               interval('[', -1e3, 1e3, ']')),
          K::number("track_ramp_time", "s", "pass-rate ramp-in time constant T_r", field(&P::track_ramp_time),
                    kDuration),
          azEl("track_amplitude", "rad", "nutation amplitude A", field(&P::track_amplitude), kAngle),
          azEl("track_period", "s", "nutation period P", field(&P::track_period), interval('[', 1e-6, 1e9, ']')),
      },
      nullptr, {}, {}};
  return table;
}

namespace {

bool hasFlatProfileKey(const YAML::Node& root) {
  for (const auto& kv : root) {
    if (kv.first.IsScalar() && kv.first.Scalar().rfind("profile.", 0) == 0) return true;
  }
  return false;
}

}  // namespace

TargetProfile loadTargetProfileText(const std::string& yaml, const std::string& origin) {
  // A file without the section (a scene, say) would give the default profile
  // silently: a truth pointing error against a target nobody chose.
  // Both spellings of a controller file name it: the section, or flat
  // `profile.*` keys (as pointing_controller --print-config writes them).
  YAML::Node root;
  if (Problem why; loadDocument(yaml, origin, root, why) && root.IsMap() && !root["profile"] && !hasFlatProfileKey(root)) {
    throw InputError(std::vector<Problem>{{origin + ": key 'profile': missing: a target profile needs the profile: "
                                           "section (or profile.* keys) of a controller configuration (e.g. controllers/config/default.yaml)",
                                           "profile", origin, 0, 0, 0}});
  }
  return loadKeys<InputError>(profileSection(), yaml, origin, {});
}

TargetProfile loadTargetProfile(const std::string& path) {
  std::string text;
  std::string why;
  if (!readFile(path, text, &why)) throw InputError(path + ": cannot open profile file: " + why);
  return loadTargetProfileText(text, path);
}

}  // namespace gimbalsim::pointing
