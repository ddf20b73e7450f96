// The plant's rejection of the controller's commands in the in-process loop:
// a run the plant refused is not ok, and commands rejected in a row end it
// where the lockstep bench ends it (firmware_sim exit 3).
#include <gtest/gtest.h>

#include "controllers/closed_loop_util.hpp"
#include "gimbalsim/contract/messages.hpp"
#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/firmware_sim/plant_scene.hpp"
#include "test_util.hpp"

namespace gimbalsim::controllers {
namespace {

ControllerConfig defaultConfig(const std::vector<std::string>& sets = {}) {
  return loadControllerConfig(test::defaultControllerConfig(), sets);
}

// A controller none of whose commands the plant takes (beyond the firmware's
// sanity range: torque.limit 1 N m, commands of 50 N m) controlled nothing:
// the run is not ok and says why, as the bench exits 3 (it was "ok").
TEST(CommandRejection, ARunWhoseEveryCommandThePlantRejectedIsNotOk) {
  const ControllerConfig c = defaultConfig({"profile.start=[0.1, 0.1]"});
  ClosedLoopOptions opt;
  opt.duration = 0.02;
  const ClosedLoopResult r = runClosedLoop(test::scene("paper_clearance", {"torque.limit=[1, 1]"}), c, opt);
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(r.rejected_stop);
  EXPECT_EQ(r.commands_rejected, 20);  // ticks 0 .. 19: the last tick's answer comes after the run
  EXPECT_EQ(r.error, "the plant accepted none of the controller's 20 commands (torque beyond the sanity range)");
}

// (pass 103) a run too short for 30 in a row whose plant took only t = 0's command (the profile's rest) and
// rejected the 9 after it (a track of 1000 rad at 1 MHz, the controller's limit 1e6 N m) ended "ok" with figures
// of a run the controller never acted on; below kStatusesToJudge rejected it is not judged
TEST(CommandRejection, AShortRunWhosePlantTookFewerThanItTakesToJudgeIsNotOk) {
  const ControllerConfig c = defaultConfig(
      {"profile.slew_start=0", "profile.slew_time=1e-6", "profile.hold_time=0", "profile.track_amplitude=[1000, 1000]",
       "profile.track_period=[1e-6, 1e-6]", "azimuth.torque_limit=1e6", "elevation.torque_limit=1e6"});
  ClosedLoopOptions opt;
  opt.duration = 0.01;
  const ClosedLoopResult r = runClosedLoop(test::scene("paper_ideal"), c, opt);
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(r.rejected_stop);
  EXPECT_EQ(r.error, "the plant accepted only 1 of the controller's 10 commands (torque beyond the sanity range)");
  opt.duration = 0.003;  // 1 taken, 2 rejected: too few to judge
  EXPECT_TRUE(runClosedLoop(test::scene("paper_ideal"), c, opt).ok);
}

// A plant that rejects the commands in a row ends the run where the lockstep bench ends it (exit 3 after
// kRejectedInARow), not "ok" over a run it mostly refused (pass 56: torque.limit 1 N m, a 50 N m slew
// command rejected for seconds, ok in process, exit 3 on the bench).
TEST(CommandRejection, CommandsRejectedInARowStopTheRunAsTheBenchDoes) {
  ClosedLoopOptions opt;
  opt.duration = 0.5;
  const ControllerConfig c = defaultConfig({"profile.start=[0.1, 0.1]"});
  const ClosedLoopResult r = runClosedLoop(test::scene("paper_clearance", {"torque.limit=[1, 1]"}), c, opt);
  EXPECT_FALSE(r.ok);
  EXPECT_TRUE(r.rejected_stop);
  EXPECT_EQ(r.commands_rejected, contract::kRejectedInARow);
  EXPECT_EQ(r.error, "the plant accepted none of the controller's last 30 commands (torque beyond the sanity "
                     "range): stopped at t = 0.029 s, as the lockstep bench stops");
  // From the profile's rest the first commands are small and taken; the slew's are not, for longer than 30 ticks.
  opt.duration = 3.0;
  const ClosedLoopResult slew = runClosedLoop(test::scene("paper_clearance", {"torque.limit=[1, 1]"}), defaultConfig(), opt);
  EXPECT_FALSE(slew.ok);
  EXPECT_TRUE(slew.rejected_stop);
  EXPECT_GT(slew.t_end, 0.5);  // the slew starts at 0.5 s
  EXPECT_LT(slew.t_end, 2.5);
  EXPECT_NE(slew.error.find("last 30 commands"), std::string::npos) << slew.error;
  // The scene's own limit takes every command: the run is ok.
  const ClosedLoopResult fine = runClosedLoop(test::scene("paper_clearance"), defaultConfig(), opt);
  EXPECT_TRUE(fine.ok) << fine.error;
  EXPECT_EQ(fine.commands_rejected, 0);
}

}  // namespace
}  // namespace gimbalsim::controllers
