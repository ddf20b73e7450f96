// How a bench run ends: firmware_sim and pointing_controller started with the
// same --duration both end by themselves (the controller counts the run's
// statuses as the plant does: 0 .. T / period - 1), and a controller whose
// plant has gone says so and exits with the no-peer code (6) by itself.
// Every wait is bounded (timeout), so a hang fails instead of blocking.
#include "hil_util.hpp"

namespace gimbalsim::hil {
namespace {

/// The script of a lockstep pair on url: pointing_controller (default config, ctl_flags) in the background,
/// firmware_sim on scene (--lockstep, fw_flags) in front, each bounded by timeout; true (exit 0) when
/// firmware_sim exited fw_exit and the controller ctl_exit. Logs: ctl.log, fw.log.
std::string lockstepPair(const std::string& url, const std::string& ctl_flags, const std::string& scene,
                         const std::string& fw_flags, int fw_exit, int ctl_exit) {
  const std::string cfg = defaultControllerConfig();
  return "timeout 60 " + pointingController() + " " + cfg + " --lcm-url '" + url + "' " + ctl_flags +
         " >ctl.log 2>&1 &\nC=$!\ntimeout 60 " + firmwareSim() + " " + scenePath(scene) + " --lockstep --profile " +
         cfg + " --lcm-url '" + url + "' " + fw_flags + " >fw.log 2>&1\nrf=$?\nwait $C; rc=$?\necho \"rf $rf rc $rc\"\n" +
         "[ $rf -eq " + std::to_string(fw_exit) + " ] && [ $rc -eq " + std::to_string(ctl_exit) + " ]";
}

TEST(HilDuration, LockstepPairWithTheSameDurationBothEndByThemselves) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("duration");
  // No --idle-exit, no kill: each process must end on its own within the bound (timeout gives 124).
  const std::string body =
      lockstepPair(udpmUrl(7791), "--duration 1", "paper_clearance", "--duration 1 --start-timeout 20", 0, 0);
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "fw.log") << readFile(dir / "ctl.log");
  EXPECT_NE(readFile(dir / "ctl.log").find("answered 1000 statuses (last t = 0.999 s)"), std::string::npos)
      << readFile(dir / "ctl.log");
  EXPECT_NE(readFile(dir / "fw.log").find("lockstep timeouts 0"), std::string::npos) << readFile(dir / "fw.log");
  // Each process names the limit it counts (docs/usage.md "Torque limits"): the slew's first
  // ticks hold the controller at its own 50 N m; the plant's 1000 N m motor is never reached.
  const std::string ctl = readFile(dir / "ctl.log"), fw = readFile(dir / "fw.log");
  const std::string own = " with the command at its own torque limit (azimuth/elevation.torque_limit)";
  const std::size_t at = ctl.find(own);
  ASSERT_NE(at, std::string::npos) << ctl;
  EXPECT_NE(fw.find("ticks at the motor limit (torque.limit) 0\n"), std::string::npos) << fw;
  // A run of 1 s ends before the track (from 3.5 s): both summaries say n/a and why, never an error of 0.
  const std::string why = "n/a (track window [3.5, inf) s not reached: run ended at 0.999 s)";
  EXPECT_NE(readFile(dir / "ctl.log").find("max |joint error| while tracking " + why), std::string::npos)
      << readFile(dir / "ctl.log");
  EXPECT_NE(readFile(dir / "fw.log").find("; while tracking: " + why), std::string::npos) << readFile(dir / "fw.log");
}

TEST(HilDuration, ControllerWhosePlantIsKilledSaysSoAndExitsSix) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("plant_gone");
  const std::string url = udpmUrl(7792), cfg = defaultControllerConfig();
  // The plant runs until killed (no --duration); the controller has no flag that would end it but its default.
  const std::string body =
      std::string(kStartedFn) + "timeout 60 " + pointingController() + " " + cfg + " --lcm-url '" + url +
      "' >ctl.log 2>&1 &\nC=$!\nstarted ctl.log 'pointing_controller: GIMBAL_STATUS' || exit 90\n" + firmwareSim() +
      " " + scenePath("paper_ideal") + " --rt-priority 0 --lcm-url '" + url + "' >fw.log 2>&1 &\nF=$!\n" +
      "started fw.log 'firmware_sim: scene' || exit 91\nsleep 0.5\nkill -9 $F\nwait $C; rc=$?\necho \"rc $rc\"\n"
      "[ $rc -eq 6 ]";
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "ctl.log");
  const std::string ctl = readFile(dir / "ctl.log");
  EXPECT_NE(ctl.find("pointing_controller: the plant has gone: no status for 3 s (--plant-timeout) after status"),
            std::string::npos)
      << ctl;
  EXPECT_NE(ctl.find("answered"), std::string::npos) << "its summary";
}


// The other side: a lockstep plant whose controller has gone (here: it ended
// its shorter run) stops after --start-timeout without an answer, exit 6,
// instead of paying --lockstep-timeout-ms on every tick for ever.
TEST(HilDuration, LockstepPlantWhoseControllerHasGoneSaysSoAndExitsSix) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("controller_gone");
  // The controller answers within --lockstep-timeout-ms until it ends: 250 ms,
  // as a loaded 2-core VM stalls a process for tens of ms (50 ms failed once).
  const std::string body = lockstepPair(udpmUrl(7793), "--duration 0.5", "paper_ideal",
                                        "--duration 100 --lockstep-timeout-ms 250 --start-timeout 10 "
                                        "--truth-csv truth.csv", 6, 0);
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "fw.log") << readFile(dir / "ctl.log");
  const std::string fw = readFile(dir / "fw.log");
  EXPECT_NE(fw.find("firmware_sim: lockstep: no command answered the last 40 statuses (10 s of --lockstep-timeout-ms 250): "
                    "the controller has gone; stopping at t = 0.540 s"),
            std::string::npos)
      << fw;
  EXPECT_NE(fw.find("commands: received 500"), std::string::npos) << "its summary\n" << fw;
}

// A plant that stops (here its velocity limit, at t = 0.5 s) ends the run for both: firmware_sim exits 3 and
// so does its controller, which saw FAULT_PLANT_FAULT in the statuses after the stop (it exited 0, pass 55).
TEST(HilDuration, LockstepPairWhosePlantStopsBothExitThree) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("plant_stops");
  const std::string body = lockstepPair(udpmUrl(7794), "--duration 0.8", "paper_clearance",
                                        "--duration 0.8 --start-timeout 20 --set sim.velocity_limit=0.001", 3, 3);
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "fw.log") << readFile(dir / "ctl.log");
  const std::string ctl = readFile(dir / "ctl.log");
  EXPECT_NE(ctl.find("pointing_controller: the plant stopped after t = 0.5"), std::string::npos) << ctl;
}

// The same stop with a controller that has no --duration: the plant ends at 0.8 s, the controller hears nothing
// for --plant-timeout and ends as the stopped run it was (3), not as a bench whose plant went missing (6, pass 56).
TEST(HilDuration, ControllerWithoutDurationWhosePlantStoppedAndEndedExitsThree) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("plant_stops_open");
  const std::string url = udpmUrl(7796), cfg = defaultControllerConfig();
  const std::string body =
      "timeout 60 " + pointingController() + " " + cfg + " --lcm-url '" + url + "' --plant-timeout 1 >ctl.log 2>&1 &\n"
      "C=$!\ntimeout 60 " + firmwareSim() + " " + scenePath("paper_clearance") + " --lockstep --duration 0.8 --profile " +
      cfg + " --lcm-url '" + url + "' --start-timeout 20 --set sim.velocity_limit=0.001 >fw.log 2>&1\nrf=$?\n"
      "wait $C; rc=$?\necho \"rf $rf rc $rc\"\n[ $rf -eq 3 ] && [ $rc -eq 3 ]";
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "fw.log") << readFile(dir / "ctl.log");
  const std::string ctl = readFile(dir / "ctl.log");
  EXPECT_NE(ctl.find("after it had stopped (FAULT_PLANT_FAULT)"), std::string::npos) << ctl;
}

}  // namespace
}  // namespace gimbalsim::hil
