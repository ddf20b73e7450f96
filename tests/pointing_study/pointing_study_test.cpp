// gimbalsim_pointing_study --quick: the summary has its columns and one row
// per run (ideal + two clearances), the time series one column per run, and
// the ideal joint's peak tracking error is finite and positive. Bad arguments
// and an unwritable output directory are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>
#include <sys/wait.h>

#include "../csv_util.hpp"

namespace {

int run(const std::string& args, const std::string& log) {
  // The scenes named: the program reads no source folder unasked.
  const std::string cmd = std::string(GIMBALSIM_POINTING_STUDY_BIN) + " --ideal-scene " GIMBALSIM_SCENES_DIR
                          "/paper_ideal.yaml --clearance-scene " GIMBALSIM_SCENES_DIR "/paper_clearance.yaml " + args +
                          " > " + log + " 2>&1";
  const int st = std::system(cmd.c_str());
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

TEST(PointingStudy, QuickRunWritesOneSummaryRowPerRun) {
  const std::string dir = std::string(GIMBALSIM_TEST_TMP) + "/quick";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  ASSERT_EQ(run("--quick --out " + dir, dir + ".log"), 0) << "see " << dir << ".log";
  const gimbalsim::test::Csv sum = gimbalsim::test::Csv::read(dir + "/summary.csv");
  const std::vector<std::string> cols{"run",          "scene",        "clearance_m", "peak_track_rad",
                                      "rms_track_rad", "peak_run_rad", "track_ticks", "status",
                                      "stop_reason", "track_reason"};
  EXPECT_EQ(sum.header, cols);
  ASSERT_EQ(sum.rows.size(), 3u);
  const auto rec = sum.records();
  EXPECT_EQ(rec[0].at("run"), "ideal");
  EXPECT_EQ(rec[0].at("scene"), "paper_ideal");
  EXPECT_EQ(rec[0].at("status"), "ok") << rec[0].at("stop_reason");
  const double peak = std::stod(rec[0].at("peak_track_rad"));
  EXPECT_TRUE(std::isfinite(peak));
  EXPECT_GT(peak, 0.0);
  EXPECT_GT(std::stoll(rec[0].at("track_ticks")), 0);
  EXPECT_EQ(rec[0].at("track_reason"), "");
  for (int i = 1; i < 3; ++i) {
    EXPECT_EQ(rec[i].at("scene"), "paper_clearance");
    EXPECT_GT(std::stod(rec[i].at("clearance_m")), 0.0);
  }
  const gimbalsim::test::Csv ts = gimbalsim::test::Csv::read(dir + "/pointing_error.csv");
  ASSERT_EQ(ts.header.size(), 4u);
  EXPECT_EQ(ts.header[0], "t_s");
  EXPECT_EQ(ts.header[1], "error_ideal_rad");
  EXPECT_EQ(ts.header[2], "error_c0p25mm_rad");  // the run c=0.25mm
  EXPECT_GT(ts.rows.size(), 100u);
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(PointingStudy, RefusesBadArgumentsNamingTheOption) {
  const std::string log = std::string(GIMBALSIM_TEST_TMP) + "/refused.log";
  const std::string out = " --out " + std::string(GIMBALSIM_TEST_TMP);
  for (const auto& [args, option] : std::vector<std::pair<std::string, std::string>>{
           {"--duration -1", "--duration"},
           {"--duration abc", "--duration"},
           {"--clearances 0.1e-3,-1", "--clearances"},
           {"--set no.such_key=1", "--set"},
           {"--scene-set contact.clearance=0.02", "--scene-set"},
           {"--bogus", "--bogus"}}) {
    EXPECT_EQ(run(args + out, log), 2) << args;
    EXPECT_NE(slurp(log).find(option), std::string::npos) << args << ": " << slurp(log);
  }
}

// A run that ends before the track has no tracking figure: nan and the
// reason in summary.csv, n/a on the console, never 0; the time series and the
// peak over the run (which need no window) are still written, exit 0.
TEST(PointingStudy, ARunThatEndsBeforeTheTrackHasNanTrackFiguresWithTheReason) {
  const std::string dir = std::string(GIMBALSIM_TEST_TMP) + "/short";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  ASSERT_EQ(run("--duration 2 --clearances 0.5e-3 --out " + dir, dir + ".log"), 0) << slurp(dir + ".log");
  const std::string why = "track window [3.5, inf) s not reached: run ended at 2 s";
  const auto rec = gimbalsim::test::Csv::read(dir + "/summary.csv").records();
  ASSERT_EQ(rec.size(), 2u);
  for (const auto& r : rec) {
    EXPECT_EQ(r.at("peak_track_rad"), "nan");
    EXPECT_EQ(r.at("rms_track_rad"), "nan");
    EXPECT_EQ(r.at("track_reason"), "track window [3.5; inf) s not reached: run ended at 2 s");  // no comma in a cell
    EXPECT_EQ(r.at("status"), "ok");
    EXPECT_GT(std::stod(r.at("peak_run_rad")), 0.0);
  }
  EXPECT_NE(slurp(dir + ".log").find("n/a (" + why + ")"), std::string::npos) << slurp(dir + ".log");
}

TEST(PointingStudy, FailedWritesAreReportedNamingTheFile) {
  const std::string tmp = std::string(GIMBALSIM_TEST_TMP);
  // A missing output folder is refused before running, naming it (exit 2): no program creates one.
  std::filesystem::remove_all(tmp + "/missing");
  EXPECT_EQ(run("--duration 0.01 --clearances 0.5e-3 --out " + tmp + "/missing/sub", tmp + "/missing.log"), 2);
  EXPECT_NE(slurp(tmp + "/missing.log").find(tmp + "/missing/sub': no such folder"), std::string::npos)
      << slurp(tmp + "/missing.log");
  EXPECT_FALSE(std::filesystem::exists(tmp + "/missing"));
  // summary.csv cannot be opened: a directory has its name (refused before running: exit 2).
  const std::string dir = tmp + "/unwritable";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir + "/summary.csv");
  EXPECT_EQ(run("--duration 0.01 --clearances 0.5e-3 --out " + dir, dir + ".log"), 2);
  const std::string text = slurp(dir + ".log");
  EXPECT_NE(text.find(dir + "/summary.csv"), std::string::npos) << text;
}

}  // namespace
