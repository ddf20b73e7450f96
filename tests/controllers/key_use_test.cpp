// Which controller keys a configuration reads (controllers/src/key_use.cpp): the one table the study programs
// and the Python sweeps refuse a recorded-but-idle --set by.
#include <gtest/gtest.h>

#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/controllers/key_use.hpp"

namespace gimbalsim::controllers {
namespace {

ControllerConfig config(const std::vector<std::string>& sets) {
  return loadControllerConfigText("", "test", sets);
}

TEST(KeyUse, AKeyIsReadOnlyUnderItsSetting) {
  EXPECT_EQ(controllerKeyIdle(config({"control.rate_source=status"}), "control.rate_filter_hz", false),
            "the controller reads it only with control.rate_source difference; it has control.rate_source status");
  EXPECT_EQ(controllerKeyIdle(config({"control.rate_source=difference"}), "control.rate_filter_hz", false), "");
  // a key under no condition is read by every configuration
  EXPECT_EQ(controllerKeyIdle(config({}), "azimuth.kp", false), "");
}

TEST(KeyUse, EveryConditionMustHoldAndAnyAlternativeDoes) {
  const auto joint = config({"pointing.mode=joint", "pointing.target=fixed"});
  EXPECT_NE(controllerKeyIdle(joint, "pointing.fixed_direction", false).find("pointing.mode inertial"),
            std::string::npos);
  const auto profile = config({"pointing.mode=inertial", "pointing.target=profile"});
  EXPECT_NE(controllerKeyIdle(profile, "pointing.fixed_direction", false).find("it has pointing.target profile"),
            std::string::npos);
  EXPECT_EQ(controllerKeyIdle(config({"pointing.mode=inertial", "pointing.target=fixed"}), "pointing.fixed_direction",
                              false),
            "");
  // the joint axes: the inertial mode or the model feed-forward, either one
  EXPECT_EQ(controllerKeyIdle(config({"pointing.mode=joint", "pointing.accel_feedforward=model"}), "gimbal.joint1_axis",
                              false),
            "");
  EXPECT_NE(controllerKeyIdle(config({"pointing.mode=joint", "pointing.accel_feedforward=profile"}),
                              "gimbal.joint1_axis", false),
            "");
}

TEST(KeyUse, APrefixRuleCoversItsKeys) {
  EXPECT_NE(controllerKeyIdle(config({"pointing.accel_feedforward=profile"}), "plant.base_mass", false), "");
  EXPECT_EQ(controllerKeyIdle(config({"pointing.accel_feedforward=model"}), "plant.base_mass", false), "");
}

TEST(KeyUse, TheAntennaKeysActWhereTheLoopClosesAtTheAntenna) {
  const auto use = config({"antenna.tracker=use"});
  EXPECT_NE(controllerKeyIdle(use, "antenna.bandwidth", false).find("sensors.antenna is none"), std::string::npos);
  EXPECT_EQ(controllerKeyIdle(use, "antenna.bandwidth", true), "");
  EXPECT_NE(controllerKeyIdle(config({"antenna.tracker=ignore"}), "antenna.bandwidth", true).find("is ignore"),
            std::string::npos);
  // antenna.tracker itself decides: read wherever there is an antenna sensor
  EXPECT_EQ(controllerKeyIdle(config({"antenna.tracker=ignore"}), "antenna.tracker", true), "");
}

TEST(KeyUse, AnOverrideIsNamedByItsFlagAndCount) {
  const auto c = config({"control.rate_source=status"});
  EXPECT_EQ(idleControllerOverride("--set", {"azimuth.kp=100", "control.rate_filter_hz=50"}, c, false, {}),
            "--set #2 'control.rate_filter_hz=50': not read by these runs (the controller reads it only with "
            "control.rate_source difference; it has control.rate_source status): the value would be recorded but "
            "never act");
  EXPECT_EQ(idleControllerOverride("--set", {"monitor.hold_ticks=5"}, c, false, {{"monitor.hold_ticks", "why"}}),
            "--set #1 'monitor.hold_ticks=5': not read by these runs (why): the value would be recorded but never act");
  EXPECT_EQ(idleControllerOverride("--set", {"azimuth.kp=100"}, c, false, {{"monitor.hold_ticks", "why"}}), "");
}

// (pass 99) the joint law feeds forward the profile's acceleration: 'inertial' there ran as profile, recorded
TEST(KeyUse, TheInertialFeedForwardInJointModeIsRefusedNamingItsSet) {
  const auto joint_inertial = config({"pointing.mode=joint", "pointing.accel_feedforward=inertial"});
  EXPECT_NE(controllerValueRunsAsAnother(joint_inertial).find("runs as profile"), std::string::npos);
  EXPECT_EQ(controllerValueRunsAsAnother(config({"pointing.mode=joint", "pointing.accel_feedforward=profile"})), "");
  EXPECT_EQ(controllerValueRunsAsAnother(config({"pointing.accel_feedforward=inertial"})), "");
  const std::string why = idleControllerOverride(
      "--set", {"azimuth.kp=100", "pointing.mode=joint", "pointing.accel_feedforward=inertial"}, joint_inertial, false,
      {});
  EXPECT_EQ(why.rfind("--set #3 'pointing.accel_feedforward=inertial': pointing.accel_feedforward inertial runs as "
                      "profile with pointing.mode joint",
                      0),
            0u)
      << why;
  // (pass 104, 107) no override names it: the file's line does (it said "the controller configuration")
  const auto in_file = loadControllerConfigText("pointing:\n  mode: joint\n  accel_feedforward: inertial\n", "c.yaml");
  const std::string file_why = idleControllerOverride("--set", {"azimuth.kp=100"}, in_file, false, {});
  EXPECT_EQ(file_why.rfind("c.yaml:3:3: key 'pointing.accel_feedforward': pointing.accel_feedforward inertial runs "
                           "as profile",
                           0),
            0u)
      << file_why;
  EXPECT_EQ(in_file.runs_as_another.line, 3);
  // the mode given last (an override over the file's feed-forward) is where it was decided
  const auto mode_set = loadControllerConfigText("pointing:\n  accel_feedforward: inertial\n", "c.yaml",
                                                 {"azimuth.kp=1", "pointing.mode=joint"});
  EXPECT_EQ(mode_set.runs_as_another.set_index, 2);
  EXPECT_EQ(mode_set.runs_as_another.key, "pointing.mode");
  EXPECT_EQ(config({"pointing.mode=joint"}).runs_as_another.text, "");
}

}  // namespace
}  // namespace gimbalsim::controllers
