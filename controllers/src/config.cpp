#include "gimbalsim/controllers/config.hpp"

#include <cmath>
#include <numbers>

#include "gimbalsim/controllers/key_use.hpp"
#include "gimbalsim/controllers/model_feedforward.hpp"
#include "gimbalsim/input/value_format.hpp"
#include "gimbalsim/pointing/profile_keys.hpp"

namespace gimbalsim::controllers {
namespace {

/// The gains and limits of one axis (azimuth.*, elevation.*).
std::vector<Key<AxisGains>> gainKeys() {
  using K = Keys<AxisGains>;
  return {
      // Upper bounds keep every product of the law finite (gain x error, inertia x acceleration).
      K::number("kp", "N m/rad", "proportional gain", field(&AxisGains::kp), interval('[', 0.0, 1e9, ']')),
      K::number("ki", "N m/(rad s)", "integral gain", field(&AxisGains::ki), interval('[', 0.0, 1e12, ']')),
      K::number("kd", "N m s/rad", "derivative gain", field(&AxisGains::kd), interval('[', 0.0, 1e9, ']')),
      K::number("inertia", "kg m^2", "acceleration feed-forward inertia estimate (0: none)",
                field(&AxisGains::inertia), interval('[', 0.0, 1e6, ']')),
      K::number("torque_limit", "N m", "command limit", field(&AxisGains::torque_limit), interval('(', 0.0, 1e6, ']')),
      K::number("aw_gain", "1/s", "back-calculation anti-windup gain 1/T_t", field(&AxisGains::aw_gain),
                interval('[', 0.0, 1e6, ']')),
      K::number("play_inertia", "kg m^2",
                "inertia on the motor's side of a play in this axis's drive: inside the play the rate gain is "
                "at most 0.5 play_inertia / control.period with the antenna's sensors heard, 0.375 without "
                "(0: no backlash guard)",
                field(&AxisGains::play_inertia), interval('[', 0.0, 1e6, ']')),
  };
}

std::vector<Key<ControllerConfig>> keys() {
  using K = Keys<ControllerConfig>;
  std::vector<Key<ControllerConfig>> v = {
      K::number("control.period", "s", "control period Ts; profile time of status k is k Ts",
                field(&ControllerConfig::period), interval('[', 1e-6, 1e3, ']')),
      K::choice<AntiWindup>("control.anti_windup", "integrator anti-windup", field(&ControllerConfig::anti_windup),
                            {{"none", AntiWindup::None},
                             {"clamping", AntiWindup::Clamping},
                             {"back_calculation", AntiWindup::BackCalculation}}),
      K::choice<RateSource>(
          "control.rate_source",
          "rate in the derivative term: the status rates, or the filtered difference of the encoder angles",
          field(&ControllerConfig::rate_source), {{"status", RateSource::Status}, {"difference", RateSource::Difference}}),
      K::number("control.rate_filter_hz", "Hz",
                "low-pass cutoff of the differenced rate (read with control.rate_source difference), "
                "< 1/(2 control.period) there",
                field(&ControllerConfig::rate_filter_hz), interval('(', 0.0, 1e6, ']')),
      K::number("control.approach_margin", "-",
                "large-error approach: closing rate <= sqrt(2 a |e|), a = margin torque_limit / inertia (0: plain PD)",
                field(&ControllerConfig::approach_margin), interval('[', 0.0, 100.0, ']')),
  };
  v.push_back(K::choice<PointingMode>(
      "pointing.mode",
      "inertial: joint references from the inertial target through the estimated base attitude and the gimbal IK; "
      "joint: the profile's angles as joint references (the base's reaction rotation unseen)",
      field(&ControllerConfig::pointing_mode), {{"inertial", PointingMode::Inertial}, {"joint", PointingMode::Joint}}));
  v.push_back(K::choice<PointingTarget>(
      "pointing.target",
      "inertial target (inertial mode): profile: the profile's azimuth, elevation as a direction at the initial base "
      "pose (as the truth); fixed: pointing.fixed_direction",
      field(&ControllerConfig::target), {{"profile", PointingTarget::Profile}, {"fixed", PointingTarget::Fixed}}));
  v.push_back(K::vector<3>("pointing.fixed_direction", "-",
                           "inertial target direction with pointing.target = fixed (inertial = base frame at t = 0)",
                           field(&ControllerConfig::fixed_direction), nonZero()));
  v.push_back(K::choice<AccelFeedForward>(
      "pointing.accel_feedforward",
      "what the acceleration feed-forward inertia x a takes for a (inertial mode): profile: the profile's joint "
      "acceleration; inertial: each shaft's inertial angular acceleration about its joint, from the IK's second "
      "derivative (its curvature, the base's rate and angular acceleration), times the inertias azimuth.inertia, "
      "elevation.inertia, gimbal.azimuth_inertia_cos2; model: the computed torque of the free-floating plant's "
      "rigid-body model (plant.*), the base's reaction predicted by it; inertial needs pointing.mode inertial (in "
      "joint mode it would run as profile: refused by the programs, closed_loop and the studies' specs)",
      field(&ControllerConfig::accel_feedforward),
      {{"profile", AccelFeedForward::Profile},
       {"inertial", AccelFeedForward::Inertial},
       {"model", AccelFeedForward::Model}}));
  v.push_back(K::number("pointing.feedforward_lead", "s",
                        "the feed-forward torque is extrapolated this far ahead by its backward difference (a "
                        "command acts from the next tick on, over one period: 1.5 control.period; 0: none)",
                        field(&ControllerConfig::feedforward_lead), interval('[', 0.0, 1.0, ']')));
  v.push_back(K::number("pointing.base_accel_filter_hz", "Hz",
                        "low-pass cutoff of the base's angular acceleration (the bias-corrected gyro rate differenced "
                        "over the period; read with pointing.accel_feedforward inertial), < 1/(2 control.period) "
                        "there",
                        field(&ControllerConfig::base_accel_filter_hz), interval('(', 0.0, 1e6, ']')));
  v.push_back(K::vector<3>("gimbal.joint1_axis", "-", "azimuth axis the controller assumes, base frame",
                           [](auto& c) -> auto& { return c.gimbal.joint1_axis; }, nonZero()));
  v.push_back(K::vector<3>("gimbal.joint2_axis", "-", "elevation axis the controller assumes, shaft 1 frame",
                           [](auto& c) -> auto& { return c.gimbal.joint2_axis; }, nonZero()));
  v.push_back(K::vector<3>("gimbal.boresight", "-",
                           "antenna boresight the controller assumes, shaft 2 frame; not parallel to gimbal.joint2_axis",
                           [](auto& c) -> auto& { return c.gimbal.boresight; }, nonZero()));
  v.push_back(K::number("gimbal.azimuth_inertia_cos2", "kg m^2",
                        "elevation dependence C of the azimuth inertia the feed-forward assumes: J1(theta2) = "
                        "azimuth.inertia + C (cos 2 theta2 - 1), with its velocity-product torques (0: constant)",
                        [](auto& c) -> auto& { return c.gimbal.azimuth_inertia_cos2; }, interval('[', -1e6, 1e6, ']')));
  // The plant model of accel_feedforward = model: the scene's mass keys, same frames.
  constexpr auto plant = [](auto& c) -> auto& { return c.plant; };
  constexpr auto base = [](auto& c) -> auto& { return c.plant.base; };
  constexpr auto shaft1 = [](auto& c) -> auto& { return c.plant.shaft1; };
  constexpr auto shaft2 = [](auto& c) -> auto& { return c.plant.shaft2; };
  v.push_back(K::number("plant.base_mass", "kg", "base (satellite) mass", field(base, &BodyParams::mass), bodyMass()));
  v.push_back(K::inertia("plant.base_inertia", "about the base's CoM, base frame", field(base, &BodyParams::inertia)));
  v.push_back(K::number("plant.shaft1_mass", "kg", "shaft 1 mass", field(shaft1, &BodyParams::mass), bodyMass()));
  v.push_back(K::vector<3>("plant.shaft1_com", "m", "shaft 1 CoM from joint 1, shaft 1 frame",
                           field(shaft1, &BodyParams::com), bodyOffset()));
  v.push_back(K::inertia("plant.shaft1_inertia", "about shaft 1's CoM, shaft 1 frame", field(shaft1, &BodyParams::inertia)));
  v.push_back(K::number("plant.shaft2_mass", "kg", "shaft 2 + antenna mass", field(shaft2, &BodyParams::mass), bodyMass()));
  v.push_back(K::vector<3>("plant.shaft2_com", "m", "shaft 2 CoM from joint 2, shaft 2 frame",
                           field(shaft2, &BodyParams::com), bodyOffset()));
  v.push_back(K::inertia("plant.shaft2_inertia", "about shaft 2's CoM, shaft 2 frame", field(shaft2, &BodyParams::inertia)));
  v.push_back(K::vector<3>("plant.joint1_position", "m", "joint 1 from the base CoM, base frame",
                           field(plant, &PlantMass::joint1_position_B), bodyOffset()));
  v.push_back(K::vector<3>("plant.joint2_position", "m", "joint 2 from joint 1, shaft 1 frame",
                           field(plant, &PlantMass::joint2_position_S1), bodyOffset()));
  v.push_back(K::number("estimator.k_p", "1/s", "attitude estimator correction gain (star tracker bandwidth)",
                        [](auto& c) -> auto& { return c.estimator.k_p; }, interval('[', 0.0, 1e3, ']')));
  v.push_back(K::number("estimator.k_i", "1/s^2",
                        "attitude estimator gyro-bias integral gain (error poles: s^2 + k_p s + k_i)",
                        [](auto& c) -> auto& { return c.estimator.k_i; }, interval('[', 0.0, 1e6, ']')));
  v.push_back(K::integer("monitor.stale_ticks", "ticks",
                         "a status this many ticks older than the newest attitude message is stale: the last command is held",
                         [](auto& c) -> auto& { return c.monitor.stale_ticks; }, atLeast(1)));
  v.push_back(K::integer("monitor.hold_ticks", "ticks", "stale statuses in a row beyond this: safe (zero) torque",
                         [](auto& c) -> auto& { return c.monitor.hold_ticks; }, atLeast(0)));
  v.push_back(K::integer("monitor.stuck_window", "-",
                         "consecutive statuses over which each axis's encoder motion is compared with its integrated rate",
                         [](auto& c) -> auto& { return c.monitor.stuck_window; }, atLeast(2)));
  v.push_back(K::number("monitor.stuck_tol", "rad",
                        "encoder motion and integrated rate differing by more than this over a window: encoder suspect, "
                        "the axis runs on rate feedback only",
                        [](auto& c) -> auto& { return c.monitor.stuck_tol; }, interval('(', 0.0, 1e3, ']')));
  v.push_back(K::choice<bool>(
      "antenna.tracker",
      "use: when the plant sends the antenna's boresight tracker (sensors.antenna), the position error is taken "
      "at the antenna (encoders plus the play's offset the tracker measures); ignore: encoders only",
      [](auto& c) -> auto& { return c.antenna.use_tracker; }, {{"use", true}, {"ignore", false}}));
  v.push_back(K::number("antenna.offset_rate", "rad/s",
                        "most the tracker's play offset in the position error moves per second, per axis (a first "
                        "sample or the end of an outage does not kick the command)",
                        [](auto& c) -> auto& { return c.antenna.offset_rate; }, interval('(', 0.0, 1e3, ']')));
  v.push_back(K::number("antenna.bandwidth", "rad/s",
                        "with the tracker in use: the loop at the antenna places a triple pole here on each axis's "
                        "inertia (kp = 3 J w^2, ki = J w^3, kd = 3 J w with J = azimuth.inertia, elevation.inertia)",
                        [](auto& c) -> auto& { return c.antenna.bandwidth; }, interval('(', 0.0, 1e3, ']')));
  v.push_back(K::number("antenna.motor_damping", "N m s/rad",
                        "with the tracker in use: torque per rad/s of the motor's rate against the antenna's (inside "
                        "the play the motor follows the antenna)",
                        [](auto& c) -> auto& { return c.antenna.motor_damping; }, interval('[', 0.0, 1e9, ']')));
  v.push_back(K::number("antenna.engaged_rate", "rad/s",
                        "with the tracker in use: the integral runs only while the motor's and the antenna's rates "
                        "differ by at most this (inside the play the antenna is out of the motor's reach)",
                        [](auto& c) -> auto& { return c.antenna.engaged_rate; }, interval('(', 0.0, 1e3, ']')));
  v.push_back(K::number("antenna.integral_leak_time", "s",
                        "with the tracker in use: while the motor's and the antenna's rates differ by more than "
                        "antenna.engaged_rate the integral decays toward 0 with this time constant (0: it is held)",
                        [](auto& c) -> auto& { return c.antenna.integral_leak_time; }, interval('[', 0.0, 1e6, ']')));
  embed(v, "profile.", pointing::profileKeys().keys, [](auto& c) -> auto& { return c.profile; });
  embed(v, "azimuth.", gainKeys(), [](auto& c) -> auto& { return c.axis[0]; });
  embed(v, "elevation.", gainKeys(), [](auto& c) -> auto& { return c.axis[1]; });
  return v;
}

/// Why the model feed-forward's arithmetic cannot honour these mass properties ("" when it can): at some joint
/// angles the joints' reduced inertia H* = Mqq - Mqb Mbb^-1 Mbq is not finite, or its smallest eigenvalue is
/// under 1e-12 of Mqq's largest entry, where double rounding leaves it under 4 significant digits (a base far
/// too light for its shafts): the computed torque H* ddq + c* would be rounding (pass 81: 1e9 kg shafts on a
/// 1e-6 kg base sent a NaN torque mid-slew).
std::string plantModelProblem(const ControllerConfig& c) {
  const Model m = plantModel(c.plant, c.gimbal.joint1_axis, c.gimbal.joint2_axis, c.gimbal.boresight);
  constexpr int kGrid = 12;  // joint angles over a turn each
  for (int i = 0; i < kGrid; ++i) {
    for (int j = 0; j < kGrid; ++j) {
      const Vec2 q(2.0 * std::numbers::pi * i / kGrid, 2.0 * std::numbers::pi * j / kGrid);
      const ReducedDynamics r = reducedDynamics(m, q, Vec2::Zero(), Vec3::Zero());
      const double a = r.H(0, 0), d = r.H(1, 1), b = 0.5 * (r.H(0, 1) + r.H(1, 0));
      const double smallest = 0.5 * (a + d) - std::hypot(0.5 * (a - d), b);
      if (!(r.H.allFinite() && r.A.allFinite() && smallest >= 1e-12 * r.joint_scale)) {
        const std::string at = "the model feed-forward's joint inertia at q = (" + formatNumber(q(0)) + ", " +
                               formatNumber(q(1)) + ") rad ";
        if (!(r.H.allFinite() && r.A.allFinite())) return at + "is not finite: give mass properties the model can hold";
        return at + "has its smallest eigenvalue " + formatNumber(smallest) + " kg m^2 under 1e-12 of Mqq's largest "
               "entry " + formatNumber(r.joint_scale) + " kg m^2: rounding leaves it under 4 significant digits (a "
               "base far too light for its shafts); give mass properties within a few orders of each other";
      }
    }
  }
  return "";
}

/// Where a value that runs as another was decided: the later override of the two keys, else the feed-forward's
/// place in the file (the mode's when the feed-forward is the default).
void placeValueRunningAsAnother(ControllerConfig& c, const Given& g) {
  const std::string why = controllerValueRunsAsAnother(c);
  if (why.empty()) return;
  const Problem feedforward = g.problemAt("pointing.accel_feedforward", why), mode = g.problemAt("pointing.mode", why);
  const bool mode_decides = mode.set_index > feedforward.set_index ||
                            (feedforward.set_index == 0 && feedforward.line == 0 && mode.line > 0);
  c.runs_as_another = mode_decides ? mode : feedforward;
}

/// Checks across keys (every key has passed its own check).
void validate(const ControllerConfig& c, Given& g) {
  if (c.accel_feedforward == AccelFeedForward::Model) {  // the only reader of plant.*
    if (const std::string why = plantModelProblem(c); !why.empty()) {
      std::string key = "plant.base_mass";  // named where the user gave one of the plant's keys
      for (const char* k : {"plant.base_mass", "plant.base_inertia", "plant.shaft1_mass", "plant.shaft1_com",
                            "plant.shaft1_inertia", "plant.shaft2_mass", "plant.shaft2_com", "plant.shaft2_inertia",
                            "plant.joint1_position", "plant.joint2_position"}) {
        if (g.has(k)) {
          key = k;
          break;
        }
      }
      g.refuse(key, why);
    }
  }
  // Where the law reads it (pid.cpp): a period it never filters at is no reason to refuse (a 5 ms period
  // was refusable only by a key a study then refused as unread).
  if (c.rate_source == RateSource::Difference && !(c.rate_filter_hz < 0.5 / c.period)) {
    g.refuse("control.rate_filter_hz", "must be below the Nyquist frequency 1/(2 control.period)");
  }
  // Read only by the inertial feed-forward (inertial_reference.cpp): with the model's, a 10 ms period was
  // refused for this key's default, and giving it was refused as unread (pass 55).
  if (c.accel_feedforward == AccelFeedForward::Inertial && !(c.base_accel_filter_hz < 0.5 / c.period)) {
    g.refuse("pointing.base_accel_filter_hz", "must be below the Nyquist frequency 1/(2 control.period)");
  }
  const Vec3 k1 = c.gimbal.joint1_axis.normalized(), k2 = c.gimbal.joint2_axis.normalized();
  if (k1.cross(k2).norm() < 1e-6) g.refuse("gimbal.joint2_axis", "must not be parallel to gimbal.joint1_axis");
  // The elevation joint cannot turn a boresight along its own axis (and the
  // antenna tracker's elevation reading would mean nothing: tracker_fusion.cpp).
  if (k2.cross(c.gimbal.boresight.normalized()).norm() < 1e-6) {
    g.refuse("gimbal.boresight", "must not be parallel to gimbal.joint2_axis");
  }
}

}  // namespace

const KeyTable<ControllerConfig>& controllerTable() {
  static const KeyTable<ControllerConfig> table{
      {"a controller configuration", "controller configuration file",
       "`pointing_controller --keys`, docs/controller_keys.md", ""},
      keys(), validate, placeValueRunningAsAnother, {}};
  return table;
}

std::vector<KeyInfo> controllerKeys() { return controllerTable().info(); }

std::vector<std::string> configValues(const ControllerConfig& c) { return controllerTable().values(c); }

void finalizePlant(ControllerConfig& c) {
  c.plant_model = plantModel(c.plant, c.gimbal.joint1_axis, c.gimbal.joint2_axis, c.gimbal.boresight);
}

ControllerConfig loadControllerConfigText(const std::string& yaml, const std::string& origin,
                                          const std::vector<std::string>& overrides) {
  ControllerConfig c = loadKeys<ConfigError>(controllerTable(), yaml, origin, overrides);
  finalizePlant(c);
  return c;
}

ControllerConfig loadControllerConfig(const std::string& path, const std::vector<std::string>& overrides) {
  std::string text;
  std::string why;
  if (!readFile(path, text, &why)) throw ConfigError(path + ": cannot open controller configuration file: " + why);
  return loadControllerConfigText(text, path, overrides);
}

}  // namespace gimbalsim::controllers
