// SIGINT and SIGTERM end every bench program cleanly: a real-time bench
// (firmware_sim with --truth-csv, pointing_controller with --log-csv,
// gimbalsim_record) in a private network namespace is stopped mid-run with
// SIGINT (the plant) and SIGTERM (controller, recorder). Each exits with
// 128 + the signal (130, 143: docs/usage.md "Exit codes"), prints its summary, and leaves its output whole: every CSV row complete (the file
// ends with a newline, every row has the header's columns) and the log a
// valid LCM log whose truth is the CSV's, up to the last whole row; no
// temporary file is left behind.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "hil_util.hpp"

namespace gimbalsim::hil {
namespace {

void expectWholeCsv(const std::string& path, size_t min_rows) {
  const std::string text = readFile(path);
  ASSERT_FALSE(text.empty()) << path;
  EXPECT_EQ(text.back(), '\n') << path << ": the last row is cut off";
  const Csv c = Csv::read(path);
  EXPECT_GE(c.rows.size(), min_rows) << path;
  for (size_t k = 0; k < c.rows.size(); ++k) ASSERT_EQ(c.rows[k].size(), c.header.size()) << path << " row " << k;
}

// A controller that could send no answer (every torque NaN: a profile whose slew
// lasted 1e-300 s) left a lockstep plant waiting. Such a profile is refused now,
// before LCM starts (exit 2, naming the key): no configuration within the keys'
// ranges gives a NaN torque, and the process keeps its guard (no NaN is sent;
// a run whose every answer was NaN would end with exit 3, not 0 or 6).
TEST(HilStop, AProfileWhoseTorquesWouldOverflowIsRefusedBeforeTheBench) {
  TempDir dir("hil_no_answer");
  int st = 0;
  const std::string out = runCapture(pointingController() + " " + defaultControllerConfig() +
                                         " --lcm-url memq:// --set profile.slew_start=0 --set profile.slew_time=1e-300"
                                         " --duration 0.2 2>&1",
                                     &st);
  EXPECT_EQ(WEXITSTATUS(st), 2) << out;
  EXPECT_NE(out.find("key 'profile.slew_time': must be in [1e-06, 1e+09], got 1e-300"), std::string::npos) << out;
}

TEST(HilStop, SigintAndSigtermEndEveryProgramCleanlyWithWholeOutputs) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("stop");
  const std::string url = udpmUrl(7781), cfg = defaultControllerConfig();
  const std::string body =
      std::string(kStartedFn) + "'" + std::string(GIMBALSIM_RECORD) + "' --lcm-url '" + url + "' run.lcmlog >rec.log 2>&1 &\nR=$!\n" +
      pointingController() + " " + cfg + " --lcm-url '" + url + "' --log-csv ctl.csv >ctl.log 2>&1 &\nC=$!\n" +
      "started rec.log recording && started ctl.log 'pointing_controller: GIMBAL_STATUS' || exit 90\n" +
      firmwareSim() + " " + scenePath("paper_clearance") + " --profile " + cfg +
      " --truth-csv truth.csv --lcm-url '" + url + "' >fw.log 2>&1 &\nF=$!\n" +
      "started fw.log 'firmware_sim: scene' || exit 91\nsleep 0.6\nkill -INT $F\nwait $F; rf=$?\nkill -TERM $C\nwait $C; rc=$?\nsleep 0.1\nkill -TERM $R\nwait $R; rr=$?\n"
      "echo \"rf $rf rc $rc rr $rr\"\n[ $rf -eq 130 ] && [ $rc -eq 143 ] && [ $rr -eq 143 ]";
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "fw.log")
                                      << readFile(dir / "ctl.log") << readFile(dir / "rec.log");
  EXPECT_NE(readFile(dir / "fw.log").find("commands: received"), std::string::npos) << "firmware_sim's summary";
  EXPECT_NE(readFile(dir / "ctl.log").find("answered"), std::string::npos) << "the controller's summary";
  EXPECT_NE(readFile(dir / "rec.log").find("messages -> run.lcmlog"), std::string::npos) << "the recorder's summary";
  expectWholeCsv(dir / "truth.csv", 300);
  expectWholeCsv(dir / "ctl.csv", 300);
  for (const auto& e : std::filesystem::directory_iterator(dir.path)) {
    EXPECT_NE(e.path().extension(), ".tmp") << "left behind: " << e.path();
  }
  int st = 0;
  const std::string conv = runCapture("'" + std::string(GIMBALSIM_LOG2CSV) + "' '" + (dir / "run.lcmlog") +
                                          "' --channel GIMBAL_TRUTH --out '" + (dir / "log_truth.csv") + "'",
                                      &st);
  ASSERT_EQ(st, 0) << conv;
  // The recorder stopped after the plant: the log holds every truth row the CSV has.
  EXPECT_EQ(readFile(dir / "log_truth.csv"), readFile(dir / "truth.csv"));
}

}  // namespace
}  // namespace gimbalsim::hil
