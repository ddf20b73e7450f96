// Controller configuration files: the shipped default loads; --set overrides;
// bad input is refused with file:line, key and reason.
#include <gtest/gtest.h>

#include "gimbalsim/controllers/config.hpp"

namespace gimbalsim::controllers {
namespace {

const std::string kDefault = std::string(GIMBALSIM_CONTROLLER_CONFIG_DIR) + "/default.yaml";

std::string refusal(const std::string& yaml, const std::vector<std::string>& sets = {}) {
  try {
    loadControllerConfigText(yaml, "cfg.yaml", sets);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(ControllerConfig, DefaultFileLoadsWithItsValues) {
  const ControllerConfig c = loadControllerConfig(kDefault);
  EXPECT_EQ(c.period, 1e-3);
  EXPECT_EQ(c.anti_windup, AntiWindup::BackCalculation);
  EXPECT_EQ(c.rate_source, RateSource::Status);
  EXPECT_EQ(c.axis[0].inertia, 17.01);
  EXPECT_EQ(c.axis[1].inertia, 16.91);
  EXPECT_EQ(c.gimbal.azimuth_inertia_cos2, 8.205);
  EXPECT_EQ(c.accel_feedforward, AccelFeedForward::Model);
  EXPECT_EQ(c.feedforward_lead, 1.5e-3);
  // The plant model of the feed-forward is the paper scene's (tools/scenes/paper_ideal.yaml).
  EXPECT_EQ(c.plant.base.mass, 1000.0);
  EXPECT_EQ(c.plant.base.inertia, Vec3(1000.0, 100.0, 100.0).asDiagonal().toDenseMatrix());
  EXPECT_EQ(c.plant.shaft2.com, Vec3(0.5, 0.0, 0.0));
  EXPECT_EQ(c.plant_model.shaft2.mass, 50.0);
  EXPECT_GT(c.axis[0].kp, 0.0);
  EXPECT_EQ(c.profile.slew_target, Vec2(0.5, 0.3));
}

TEST(ControllerConfig, SetOverridesTheFile) {
  const ControllerConfig c = loadControllerConfig(
      kDefault, {"azimuth.kp=123", "profile.slew_target=[0.1, -0.2]", "control.anti_windup=clamping"});
  EXPECT_EQ(c.axis[0].kp, 123.0);
  EXPECT_EQ(c.profile.slew_target, Vec2(0.1, -0.2));
  EXPECT_EQ(c.anti_windup, AntiWindup::Clamping);
}

TEST(ControllerConfig, PlantKeysRebuildTheFeedForwardModelAndAreChecked) {
  const ControllerConfig c = loadControllerConfig(kDefault, {"plant.shaft2_mass=25", "plant.base_inertia=[900, 90, 80]"});
  EXPECT_EQ(c.plant_model.shaft2.mass, 25.0);
  EXPECT_EQ(c.plant_model.I_chain[1].m, 25.0);
  EXPECT_EQ(c.plant_model.base.inertia(2, 2), 80.0);
  EXPECT_NE(refusal("plant:\n  shaft1_mass: 0\n").find("cfg.yaml:2:3: key 'plant.shaft1_mass': mass must be in [1e-6, 1e9] kg"),
            std::string::npos)
      << refusal("plant:\n  shaft1_mass: 0\n");
  // A plant model whose torques would overflow (the controller then sent NaN every tick) is refused.
  EXPECT_NE(refusal("", {"plant.shaft2_com=[1e200, 0, 0]"}).find("key 'plant.shaft2_com': must be in [-1000, 1000]"),
            std::string::npos)
      << refusal("", {"plant.shaft2_com=[1e200, 0, 0]"});
  EXPECT_NE(refusal("", {"plant.base_inertia=[1e300, 1, 1]"}).find("each entry within 1e12 kg m^2"), std::string::npos);
  EXPECT_NE(refusal("plant:\n  base_inertia: [1, -1, 1]\n").find("key 'plant.base_inertia'"), std::string::npos);
  EXPECT_NE(refusal("", {"pointing.feedforward_lead=-1e-3"}).find("key 'pointing.feedforward_lead': must be in [0, 1]"),
            std::string::npos);
}

// (pass 81) mass properties each within range whose model feed-forward is rounding: 1e9 kg shafts 1.7 km out on a
// 1e-6 kg base ran, and the controller's torque turned NaN mid-slew. Refused under the model feed-forward alone
// (no other reads plant.*); a light base whose reduced inertia still keeps its digits is accepted.
TEST(ControllerConfig, APlantModelWhoseFeedForwardIsRoundingIsRefused) {
  const std::vector<std::string> extreme{"plant.shaft2_mass=1e9",        "plant.shaft2_com=[1000,1000,1000]",
                                         "plant.shaft1_mass=1e9",        "plant.joint2_position=[1000,1000,1000]",
                                         "plant.joint1_position=[1000,1000,1000]", "plant.base_mass=1e-6",
                                         "plant.base_inertia=[1e-9,1e-9,1e-9]"};
  const std::string why = refusal("", extreme);
  EXPECT_NE(why.find("key 'plant.base_mass': the model feed-forward's joint inertia at q = (0, 0) rad has its "
                     "smallest eigenvalue"),
            std::string::npos)
      << why;
  EXPECT_NE(why.find("under 4 significant digits"), std::string::npos) << why;
  std::vector<std::string> unread = extreme;
  unread.push_back("pointing.accel_feedforward=profile");
  EXPECT_NO_THROW(loadControllerConfigText("", "cfg.yaml", unread));
  EXPECT_NO_THROW(loadControllerConfigText("", "cfg.yaml", {"plant.base_mass=1e-6", "plant.base_inertia=[1e-9,1e-9,1e-9]"}));
}

TEST(ControllerConfig, UnknownKeyNamesFileLineAndKey) {
  const std::string msg = refusal("azimuth:\n  kp: 1\n  kq: 2\n");
  EXPECT_NE(msg.find("cfg.yaml:3:3: unknown key 'azimuth.kq'"), std::string::npos) << msg;
}

TEST(ControllerConfig, BadValuesAreRefusedWithTheReason) {
  EXPECT_NE(refusal("control:\n  period: -1\n").find("cfg.yaml:2:3: key 'control.period': must be in [1e-06, 1000], got -1"),
            std::string::npos);
  // Every key has a range the law honours: a gain that would make gain x error overflow is refused.
  EXPECT_NE(refusal("azimuth:\n  kp: 1e300\n").find("key 'azimuth.kp': must be in [0, 1e+09], got 1e+300"),
            std::string::npos)
      << refusal("azimuth:\n  kp: 1e300\n");
  EXPECT_NE(refusal("elevation:\n  kd: fast\n").find("key 'elevation.kd': expected a number, got 'fast'"),
            std::string::npos);
  // (pass 42) an empty mapping was skipped and the key ran at its default; a list said only what was expected
  EXPECT_NE(refusal("azimuth:\n  kp: {}\n").find("cfg.yaml:2:3: key 'azimuth.kp': expected a number, got a map"),
            std::string::npos)
      << refusal("azimuth:\n  kp: {}\n");
  EXPECT_NE(refusal("azimuth:\n  kp: [1, 2]\n").find("key 'azimuth.kp': expected a number, got a list"),
            std::string::npos);
  EXPECT_EQ(refusal("azimuth: {}\n"), "(accepted)");  // an empty section gives nothing: nothing to refuse
  EXPECT_NE(refusal("profile:\n  start: [1]\n").find("key 'profile.start': expected [azimuth, elevation]"),
            std::string::npos);
  EXPECT_NE(refusal("", {"control.rate_source=guess"})
                .find("--set #1 'control.rate_source=guess': key 'control.rate_source': expected one of "
                      "status | difference, got 'guess'"),
            std::string::npos);
  EXPECT_NE(refusal("", {"azimuth.kp"}).find("--set #1 'azimuth.kp': expected key=value"), std::string::npos);
  EXPECT_NE(refusal("control:\n  rate_source: difference\n  rate_filter_hz: 600\n")
                .find("must be below the Nyquist frequency"),
            std::string::npos);
  // ... checked where the law reads it: with the firmware's rates, a 5 ms period loads as it is
  EXPECT_EQ(refusal("control:\n  period: 0.005\n"), "(accepted)");
  EXPECT_NE(refusal("control:\n  period: 0.005\n  rate_source: difference\n").find("Nyquist"), std::string::npos);
  // ... and the base's acceleration filter only by the inertial feed-forward: with the model's (the default),
  // a 10 ms period was refused for that filter's default 50 Hz (pass 55)
  EXPECT_EQ(refusal("control:\n  period: 0.01\n"), "(accepted)");
  EXPECT_NE(refusal("control:\n  period: 0.01\npointing:\n  accel_feedforward: inertial\n")
                .find("key 'pointing.base_accel_filter_hz': must be below the Nyquist frequency"),
            std::string::npos);
  EXPECT_NE(refusal("profile:\n  track_period: [1, 0]\n").find("key 'profile.track_period': must be in [1e-06, 1e+09]"),
            std::string::npos);
  // The profile's ranges keep every torque finite: 1e300 rad, a 1e-300 s period gave NaN commands.
  for (const char* bad : {"profile.slew_target=[1e300, 0]", "profile.start=[0, -1e308]", "profile.track_rate=[1e300, 0]",
                          "profile.track_amplitude=[0, 1e300]", "profile.track_period=[1e-300, 1]",
                          "profile.slew_start=1e300", "profile.hold_time=1e300"}) {
    EXPECT_NE(refusal("", {bad}).find("must be in"), std::string::npos) << bad << ": " << refusal("", {bad});
  }
  EXPECT_NE(refusal("control: [1, 2\n").find("cfg.yaml:"), std::string::npos);
  EXPECT_NE(refusal("- 1\n- 2\n").find("must be a mapping"), std::string::npos);
}

TEST(ControllerConfig, EveryProblemIsListed) {
  try {
    loadControllerConfigText("azimuth:\n  kp: -1\n  bogus: 1\n", "cfg.yaml", {"elevation.ki=x"});
    FAIL() << "accepted";
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.problems().size(), 3u) << e.what();
  }
}

TEST(ControllerConfig, PrintedValuesLoadBackToTheSameConfiguration) {
  const ControllerConfig a = loadControllerConfig(
      kDefault, {"azimuth.kp=0.1", "elevation.aw_gain=3.3", "profile.track_rate=[1e-3, -0.1]",
                 "control.rate_source=difference", "control.anti_windup=none", "profile.slew_start=0.3"});
  const std::vector<std::string> values = configValues(a);
  ASSERT_EQ(values.size(), controllerKeys().size());
  const ControllerConfig b = loadControllerConfigText("", "empty", values);
  EXPECT_EQ(configValues(b), values);
  EXPECT_EQ(b.axis[0].kp, 0.1);
  EXPECT_EQ(b.axis[1].aw_gain, 3.3);
  EXPECT_EQ(b.profile.track_rate, Vec2(1e-3, -0.1));
  EXPECT_EQ(b.profile.slew_start, 0.3);
  EXPECT_EQ(b.rate_source, RateSource::Difference);
  EXPECT_EQ(b.anti_windup, AntiWindup::None);
  // And they differ from the defaults, so the check above is not vacuous.
  EXPECT_NE(configValues(ControllerConfig{}), values);
}

TEST(ControllerConfig, MissingFile) {
  EXPECT_THROW(loadControllerConfig("/nonexistent/ctl.yaml"), ConfigError);
}

TEST(ControllerConfig, EveryKeyIsDocumented) {
  for (const KeyInfo& k : controllerKeys()) {
    EXPECT_FALSE(k.meaning.empty()) << k.key;
    EXPECT_FALSE(k.type.empty()) << k.key;
  }
  // + pointing.* 6, gimbal.* 4, estimator.* 2; monitor.* 4; plant.* 10; azimuth/elevation.* 7 each; antenna.* 6
  EXPECT_EQ(controllerKeys().size(), 14u + 14u + 8u + 4u + 3u + 1u + 10u + 6u);
}

TEST(ControllerConfig, PointingKeysLoadAndAreChecked) {
  const ControllerConfig d = loadControllerConfigText("{}", "empty");
  EXPECT_EQ(d.pointing_mode, PointingMode::Inertial);
  EXPECT_EQ(d.target, PointingTarget::Profile);
  const ControllerConfig c = loadControllerConfigText(
      "pointing: {mode: joint, target: fixed, fixed_direction: [0, 1, 0]}\nestimator: {k_p: 2, k_i: 0.5}\n"
      "gimbal: {joint1_axis: [0, 0, 2], joint2_axis: [1, 0, 0], boresight: [0, 1, 0]}\n",
      "text");
  EXPECT_EQ(c.pointing_mode, PointingMode::Joint);
  EXPECT_EQ(c.target, PointingTarget::Fixed);
  EXPECT_EQ(c.fixed_direction, Vec3(0, 1, 0));
  EXPECT_EQ(c.estimator.k_p, 2.0);
  EXPECT_EQ(c.estimator.k_i, 0.5);
  EXPECT_EQ(c.gimbal.joint1_axis, Vec3(0, 0, 2));
  auto refused = [](const std::vector<std::string>& sets) {
    try {
      loadControllerConfigText("{}", "empty", sets);
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(refused({"gimbal.joint2_axis=[0, 0, -1]"}).find("must not be parallel to gimbal.joint1_axis"),
            std::string::npos);
  // A boresight along the elevation axis: no joint turns it in elevation (the tracker map divided by 0).
  EXPECT_NE(refused({"gimbal.boresight=[0, -2, 0]"}).find("key 'gimbal.boresight': must not be parallel to gimbal.joint2_axis"),
            std::string::npos);
  EXPECT_NE(refused({"pointing.fixed_direction=[0, 0, 0]"}).find("must be of length at least 1e-12"),
            std::string::npos);
  // (pass 83) a short non-zero vector was refused as "must be non-zero": the message names the bound
  EXPECT_NE(refused({"gimbal.boresight=[1e-13, 0, 0]"}).find("must be of length at least 1e-12, each component "
                                                             "within 1e12, got [1e-13, 0, 0]"),
            std::string::npos);
  // a length that overflows normalised to a zero vector, and the run ended "ok"
  EXPECT_NE(refused({"pointing.fixed_direction=[1e200, 1e200, 0]"}).find("each component within 1e12"),
            std::string::npos);
  EXPECT_NE(refused({"gimbal.boresight=[0, 1e13, 0]"}).find("gimbal.boresight"), std::string::npos);
  // an integer key takes digits only, and says its range
  EXPECT_NE(refused({"monitor.stuck_window=1e3"}).find("expected a whole number (digits only), got '1e3'"),
            std::string::npos);
  EXPECT_NE(refused({"monitor.hold_ticks=9223372036854775807"}).find("must be a whole number within [-1e9, 1e9]"),
            std::string::npos);
  // a 1e-300 s slew's jerk (1/T^3) overflowed to NaN torques
  EXPECT_NE(refused({"profile.slew_time=1e-300"}).find("must be in [1e-06, 1e+09]"), std::string::npos);
  EXPECT_NE(refused({"estimator.k_p=-1"}).find("must be in [0, 1000]"), std::string::npos);
  EXPECT_NE(refused({"pointing.mode=sideways"}).find("pointing.mode"), std::string::npos);
}

}  // namespace
}  // namespace gimbalsim::controllers
