// Faults over the real bench: firmware_sim --lockstep --faults and
// pointing_controller over LCM udpm (ttl=0) in a private network namespace,
// with the demo schedule (tools/faults/demo.yaml: every kind of fault).
//  - two runs side by side give byte-identical truth CSVs (the same schedule
//    and seed give the same run);
//  - the run is the in-process closed loop's with the same schedule, bit for
//    bit (dropped and late statuses, lost and late commands included), and
//    every fault is flagged in the truth at the ticks the schedule says.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "controllers/closed_loop_util.hpp"
#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/firmware_sim/fault_schedule_io.hpp"
#include "hil_util.hpp"

namespace gimbalsim::hil {
namespace {

const std::string kDemo = std::string(GIMBALSIM_SOURCE_DIR) + "/tools/faults/demo.yaml";

std::string lockstepPair(const std::string& url, const std::string& prefix, double duration, const std::string& truth,
                         const std::string& fw_log) {
  const std::string cfg = defaultControllerConfig();
  char dur[32], ctl_dur[32];
  std::snprintf(dur, sizeof dur, "%g", duration);
  std::snprintf(ctl_dur, sizeof ctl_dur, "%g", duration);
  return "timeout 60 " + pointingController() + " " + cfg + " --lcm-url '" + url + "' --channel-prefix " + prefix +
         " --duration " + ctl_dur + " --idle-exit 5 >" + fw_log + ".ctl 2>&1 &\n" + "timeout 60 " + firmwareSim() +
         " " + scenePath("paper_clearance") + " --lockstep --duration " + dur + " --profile " + cfg +
         " --faults " + kDemo + " --truth-csv " + truth + " --lcm-url '" + url + "' --channel-prefix " + prefix +
         " --start-timeout 10 >" + fw_log + " 2>&1";
}

TEST(HilFaults, TheDemoScheduleGivesByteIdenticalRunsEqualToTheInProcessLoop) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("faults_identical");
  const double duration = 3.0;  // [s] every demo fault but the late ones (star tracker, wear, friction: tests/controllers)
  const std::string body = lockstepPair(udpmUrl(7751), "HIL_FA_", duration, dir / "a.csv", dir / "a.log") +
                           " &\nA=$!\n" +
                           lockstepPair(udpmUrl(7752), "HIL_FB_", duration, dir / "b.csv", dir / "b.log") +
                           "\nrb=$?; wait $A; ra=$?; wait; [ $ra -eq 0 ] && [ $rb -eq 0 ]";
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "a.log") << readFile(dir / "b.log");
  for (const char* log : {"a.log", "b.log"}) {
    const std::string text = readFile(dir / log);
    EXPECT_EQ(summaryCounters(text).at("lockstep_timeouts"), 0) << text;
    EXPECT_NE(text.find("scheduled faults: active in"), std::string::npos) << text;
  }
  const std::string a = readFile(dir / "a.csv"), b = readFile(dir / "b.csv");
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(a == b) << "truth CSVs of two lockstep runs with the same schedule differ";

  // The in-process loop with the same schedule: the same trajectory and flags.
  const firmware::FaultSchedule f = firmware::loadFaultSchedule(kDemo);
  controllers::ClosedLoopOptions opt;
  opt.duration = duration;
  opt.faults = &f;
  std::vector<controllers::TickRecord> ticks;
  const auto r = controllers::runClosedLoop(test::scene("paper_clearance"),
                                            controllers::loadControllerConfig(defaultControllerConfig()), opt,
                                            [&](const controllers::TickRecord& k) { ticks.push_back(k); });
  ASSERT_TRUE(r.ok) << r.error;
  const Csv c = Csv::read(dir / "a.csv");
  ASSERT_EQ(c.rows.size(), ticks.size());
  const int c_seq = c.col("seq"), c_th1 = c.col("theta1_rad"), c_th2 = c.col("theta2_rad"),
            c_inj = c.col("injected_faults");
  int mismatches = 0;
  std::int32_t all = 0;
  for (std::size_t k = 0; k < c.rows.size(); ++k) {
    ASSERT_EQ(c.integer(k, c_seq), static_cast<long long>(k));
    const std::int32_t inj = static_cast<std::int32_t>(c.integer(k, c_inj));
    all |= inj;
    if (c.num(k, c_th1) != ticks[k].theta_true(0) || c.num(k, c_th2) != ticks[k].theta_true(1) ||
        inj != ticks[k].injected_faults) {
      if (++mismatches <= 3) ADD_FAILURE() << "tick " << k << ": the bench and the in-process loop differ";
    }
  }
  EXPECT_EQ(mismatches, 0);
  // Every fault of the demo schedule that starts before 3 s was flagged.
  for (const firmware::FaultSpec& s : f.faults) {
    if (s.start >= duration) continue;
    EXPECT_NE(all & firmware::injectedBit(s.kind, s.axis), 0) << firmware::faultTypeName(s.kind) << " never flagged";
  }
}

// Every command lost on the way: the controller answered every status, yet
// controlled nothing. It says so and exits 3, never 0.
TEST(HilFaults, AControllerWhoseEveryCommandIsLostDoesNotExit0) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("faults_all_lost");
  {
    std::ofstream f(dir / "lose_all.yaml");
    f << "faults:\n  - {type: command_drop, start: 0.0, end: 10.0, probability: 1.0}\n";
  }
  const std::string cfg = defaultControllerConfig(), url = udpmUrl(7753);
  const std::string body =
      "timeout 60 " + pointingController() + " " + cfg + " --lcm-url '" + url + "' --channel-prefix HIL_FL_ " +
      "--duration 0.5 --idle-exit 5 >ctl.log 2>&1 &\nC=$!\n" + "timeout 60 " + firmwareSim() + " " +
      scenePath("paper_ideal") + " --lockstep --duration 0.5 --profile " + cfg + " --faults " + (dir / "lose_all.yaml") +
      " --lcm-url '" + url + "' --channel-prefix HIL_FL_ --start-timeout 10 >fw.log 2>&1\nwait $C; echo \"ctl=$?\"";
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "fw.log");
  const std::string ctl = readFile(dir / "ctl.log");
  EXPECT_NE(readFile(dir / "run.log").find("ctl=3"), std::string::npos) << ctl;
  EXPECT_NE(ctl.find("the plant accepted none of the commands answering"), std::string::npos) << ctl;
}

// Two controllers on one lockstep plant: it binds to the first and rejects
// every command of the second, which said "answered 200 statuses" and exited
// 0 (pass 33): both numbered their commands from 0, so the second read the
// first's acceptances as its own. It controlled nothing: exit 3, and says so.
TEST(HilFaults, AControllerWhoseEveryCommandAnotherOneOutranDoesNotExit0) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("faults_second_controller");
  const std::string cfg = defaultControllerConfig(), url = udpmUrl(7756);
  const std::string ctl = "timeout 60 " + pointingController() + " " + cfg + " --lcm-url '" + url +
                          "' --duration 0.2 --idle-exit 5";
  const std::string body = ctl + " >a.log 2>&1 &\nA=$!\nstarted a.log 'pointing_controller: GIMBAL_STATUS' || exit 90\n" +
                           ctl + " >b.log 2>&1 &\nB=$!\nstarted b.log 'pointing_controller: GIMBAL_STATUS' || exit 91\n" +
                           "timeout 60 " + firmwareSim() + " " + scenePath("paper_ideal") +
                           " --lockstep --duration 0.3 --profile " + cfg + " --lcm-url '" + url +
                           "' --start-timeout 10 >fw.log 2>&1\nwait $A; a=$?; wait $B; b=$?\necho \"a=$a b=$b\"";
  ASSERT_EQ(runInNetns(dir, std::string(kStartedFn) + body), 0) << readFile(dir / "run.log") << readFile(dir / "fw.log");
  const std::string run = readFile(dir / "run.log"), a = readFile(dir / "a.log"), b = readFile(dir / "b.log");
  // One of the two was bound (exit 0), the other controlled nothing (exit 3): which one is the race's.
  const bool a_bound = run.find("a=0 b=3") != std::string::npos, b_bound = run.find("a=3 b=0") != std::string::npos;
  EXPECT_TRUE(a_bound || b_bound) << run << a << b << readFile(dir / "fw.log");
  EXPECT_NE((a_bound ? b : a).find("the plant accepted none of the commands answering"), std::string::npos) << a << b;
}

}  // namespace
}  // namespace gimbalsim::hil
