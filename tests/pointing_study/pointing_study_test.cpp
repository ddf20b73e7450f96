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
  const std::vector<std::string> cols{"run",           "scene",        "sensors",     "clearance_m",
                                      "peak_track_rad", "rms_track_rad", "peak_run_rad", "track_ticks",
                                      "controller_limited_ticks", "controller_limited_track_ticks",
                                      "motor_limited_ticks", "joints",      "max_tilt1_rad", "max_tilt2_rad",
                                      "play_onset1_s", "play_onset2_s", "loop_sensors", "status",        "stop_reason",  "track_reason",
                                      "onset_reason"};
  EXPECT_EQ(sum.header, cols);
  ASSERT_EQ(sum.rows.size(), 3u);
  const auto rec = sum.records();
  EXPECT_EQ(rec[0].at("run"), "ideal");
  EXPECT_EQ(rec[0].at("scene"), "paper_ideal");
  EXPECT_EQ(rec[0].at("sensors"), "perfect");
  EXPECT_EQ(rec[0].at("status"), "ok") << rec[0].at("stop_reason");
  const double peak = std::stod(rec[0].at("peak_track_rad"));
  EXPECT_TRUE(std::isfinite(peak));
  EXPECT_GT(peak, 0.0);
  EXPECT_GT(std::stoll(rec[0].at("track_ticks")), 0);
  EXPECT_EQ(rec[0].at("track_reason"), "");
  // A play onset is a time or nan with its reason, axis by axis, and the ticks run.
  for (const auto& r : rec) {
    for (const char* axis : {"1", "2"}) {
      const bool never = r.at(std::string("play_onset") + axis + "_s") == "nan";
      const std::string said = std::string("axis ") + axis + " never on its backlash guard's gains in the ";
      EXPECT_EQ(r.at("onset_reason").find(said) != std::string::npos, never) << r.at("run") << ": " << r.at("onset_reason");
    }
  }
  EXPECT_NE(rec[0].at("onset_reason").find("ticks run"), std::string::npos) << rec[0].at("onset_reason");
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
           {"--sensors noisy", "--sensors"},
           {"--bogus", "--bogus"}}) {
    EXPECT_EQ(run(args + out, log), 2) << args;
    EXPECT_NE(slurp(log).find(option), std::string::npos) << args << ": " << slurp(log);
  }
}

// A run that ends before the track has no tracking figure: nan and the
// reason in summary.csv, n/a on the console, never 0; the time series and the
// peak over the run (which need no window) are still written, exit 0. A run
// ending at the track's start instant has not reached it either, and counts
// no track tick (pass 59: track_ticks 1 beside "not reached").
TEST(PointingStudy, ARunThatEndsBeforeTheTrackHasNanTrackFiguresWithTheReason) {
  for (const char* end : {"2", "3.5"}) {
    const std::string dir = std::string(GIMBALSIM_TEST_TMP) + "/short" + end;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    ASSERT_EQ(run(std::string("--duration ") + end + " --clearances 0.5e-3 --out " + dir, dir + ".log"), 0)
        << slurp(dir + ".log");
    const std::string why = std::string("track window [3.5, inf) s not reached: run ended at ") + end + " s";
    const auto rec = gimbalsim::test::Csv::read(dir + "/summary.csv").records();
    ASSERT_EQ(rec.size(), 2u);
    for (const auto& r : rec) {
      EXPECT_EQ(r.at("peak_track_rad"), "nan");
      EXPECT_EQ(r.at("rms_track_rad"), "nan");
      EXPECT_EQ(r.at("track_ticks"), "0") << end;
      EXPECT_EQ(r.at("controller_limited_track_ticks"), "nan");  // a count over the window, too (pass 42: 0)
      EXPECT_EQ(r.at("track_reason"), std::string("track window [3.5; inf) s not reached: run ended at ") + end +
                                          " s");  // no comma in a cell
      EXPECT_EQ(r.at("status"), "ok");
      EXPECT_GT(std::stod(r.at("peak_run_rad")), 0.0);
    }
    EXPECT_NE(slurp(dir + ".log").find("n/a (" + why + ")"), std::string::npos) << slurp(dir + ".log");
  }
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

// Several clearance scenes: each run at every clearance, labelled by scene.
// In closed loop the encoders do not see a tilting elevation journal, so the
// spatial bearing costs far more pointing than the planar play (measured
// 2.2e-2 against about 1e-5 rad RMS while tracking at 0.5 mm).
TEST(PointingStudy, SeveralClearanceScenesAreLabelledByScene) {
  const std::string dir = std::string(GIMBALSIM_TEST_TMP) + "/scenes";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  ASSERT_EQ(run("--quick --clearances 5e-4 --clearance-scene " GIMBALSIM_SCENES_DIR "/paper_spatial2.yaml --out " +
                    dir,
                dir + ".log"),
            0)
      << "see " << dir << ".log";
  const auto rec = gimbalsim::test::Csv::read(dir + "/summary.csv").records();
  ASSERT_EQ(rec.size(), 3u);
  EXPECT_EQ(rec[1].at("run"), "paper_clearance_c=0.5mm");
  EXPECT_EQ(rec[2].at("run"), "paper_spatial2_c=0.5mm");
  EXPECT_EQ(rec[2].at("scene"), "paper_spatial2");
  const double planar = std::stod(rec[1].at("rms_track_rad")), spatial = std::stod(rec[2].at("rms_track_rad"));
  EXPECT_GT(spatial, 100.0 * planar);
  EXPECT_GT(spatial, 1e-3);
  // The tilt is azimuth backlash for the antenna: the default controller sees
  // it and its azimuth goes onto the backlash guard's gains (docs/MODEL.md
  // 11.5) instead of driving shaft 1 across it at the limit (before the guard:
  // most ticks at the limit); the planar play never shows it.
  EXPECT_EQ(rec[1].at("controller_limited_ticks"), "0");
  EXPECT_EQ(rec[2].at("controller_limited_ticks"), "0");
  EXPECT_EQ(rec[2].at("controller_limited_track_ticks"), "0");
  EXPECT_TRUE(std::isnan(std::stod(rec[1].at("play_onset1_s"))));
  EXPECT_LT(std::stod(rec[2].at("play_onset1_s")), 1.0);  // [s] within the slew's first half second
  EXPECT_EQ(rec[2].at("loop_sensors"), "encoders+base attitude");
  // The tilt behind it, from the plant's truth: the spatial journal rides
  // near its bearing's 2c/L = 0.02 rad; the planar one and joint 1 never tilt.
  EXPECT_EQ(rec[1].at("joints"), "ideal/planar");
  EXPECT_EQ(rec[2].at("joints"), "ideal/spatial");
  EXPECT_EQ(rec[1].at("max_tilt2_rad"), "0");
  EXPECT_EQ(rec[2].at("max_tilt1_rad"), "0");
  EXPECT_GT(std::stod(rec[2].at("max_tilt2_rad")), 0.005);
  EXPECT_LT(std::stod(rec[2].at("max_tilt2_rad")), 0.024);
  const gimbalsim::test::Csv ts = gimbalsim::test::Csv::read(dir + "/pointing_error.csv");
  ASSERT_EQ(ts.header.size(), 4u);
  EXPECT_EQ(ts.header[3], "error_paper_spatial2_c0p5mm_rad");
  // Realistic sensors (the pointing budget's upper bounds): every run again,
  // labelled by its sensors; the star tracker's noise lifts the ideal joint's
  // error while tracking (measured 1.8e-5 against 7.6e-7 rad RMS).
  const std::string both = dir + "/both";
  std::filesystem::create_directories(both);
  ASSERT_EQ(run("--quick --clearances 5e-4 --sensors both --out " + both, both + ".log"), 0) << "see " << both << ".log";
  const auto rb = gimbalsim::test::Csv::read(both + "/summary.csv").records();
  ASSERT_EQ(rb.size(), 4u);
  EXPECT_EQ(rb[0].at("run"), "ideal_perfect");
  EXPECT_EQ(rb[2].at("run"), "ideal_realistic");
  EXPECT_EQ(rb[3].at("run"), "c=0.5mm_realistic");
  EXPECT_EQ(rb[3].at("sensors"), "realistic");
  EXPECT_GT(std::stod(rb[2].at("rms_track_rad")), 5.0 * std::stod(rb[0].at("rms_track_rad")));
  // The same scene twice would give two runs of one name: refused before any run.
  EXPECT_EQ(run("--quick --clearance-scene " GIMBALSIM_SCENES_DIR "/paper_clearance.yaml --out " + dir,
                dir + "-twice.log"),
            2);
  EXPECT_NE(slurp(dir + "-twice.log").find("--clearance-scene: '" GIMBALSIM_SCENES_DIR "/paper_clearance.yaml' "
                                           "given twice"),
            std::string::npos)
      << slurp(dir + "-twice.log");
  // A scene is named by its file (as gimbalsim_controller_floor names it), not by its `name:` key: a modified
  // copy read as the shipped scene, and two different files of one `name:` were "given twice" (pass 55).
  const std::string copies = dir + "-copies";
  std::filesystem::create_directories(copies + "/a");
  std::filesystem::create_directories(copies + "/o");
  std::filesystem::copy_file(GIMBALSIM_SCENES_DIR "/paper_clearance.yaml", copies + "/clr_stop.yaml",
                             std::filesystem::copy_options::overwrite_existing);
  std::filesystem::copy_file(GIMBALSIM_SCENES_DIR "/paper_clearance.yaml", copies + "/a/paper_clearance.yaml",
                             std::filesystem::copy_options::overwrite_existing);
  EXPECT_EQ(run("--clearances 5e-4 --duration 0.1 --clearance-scene " + copies + "/clr_stop.yaml --out " + copies +
                    "/o",
                copies + ".log"),
            0)
      << slurp(copies + ".log");
  const auto rc = gimbalsim::test::Csv::read(copies + "/o/summary.csv").records();
  ASSERT_EQ(rc.size(), 3u);
  EXPECT_EQ(rc[1].at("scene"), "paper_clearance");
  EXPECT_EQ(rc[2].at("scene"), "clr_stop");
  EXPECT_EQ(rc[2].at("run"), "clr_stop_c=0.5mm");
  EXPECT_EQ(run("--quick --clearance-scene " + copies + "/a/paper_clearance.yaml --out " + dir, copies + "-same.log"),
            2);
  EXPECT_NE(slurp(copies + "-same.log").find("have the same file name, which names their runs; rename one"),
            std::string::npos)
      << slurp(copies + "-same.log");
  // One file under two names (a link) is one scene given twice: it ran twice (pass 56).
  std::filesystem::remove_all(copies + "/odd");
  std::filesystem::create_directories(copies + "/odd");
  std::filesystem::remove(copies + "/link.yaml");
  std::filesystem::create_symlink(GIMBALSIM_SCENES_DIR "/paper_clearance.yaml", copies + "/link.yaml");
  EXPECT_EQ(run("--quick --clearance-scene " + copies + "/link.yaml --out " + copies + "/odd", copies + "-link.log"), 2);
  EXPECT_NE(slurp(copies + "-link.log").find("link.yaml' are one file: the same scene given twice"), std::string::npos)
      << slurp(copies + "-link.log");
  // A file name names the runs and pointing_error.csv's columns: a comma or a newline in it would shift or split
  // them (pass 56); refused before any run.
  for (const std::string& name : {std::string("a,b"), std::string("line\nbreak"), std::string("q\"uote")}) {
    const std::string odd = copies + "/" + name + ".yaml";
    std::filesystem::copy_file(GIMBALSIM_SCENES_DIR "/paper_clearance.yaml", odd,
                               std::filesystem::copy_options::overwrite_existing);
    EXPECT_EQ(run("--quick --clearance-scene '" + odd + "' --out " + copies + "/odd", copies + "-odd.log"), 2) << name;
    EXPECT_NE(slurp(copies + "-odd.log").find("may hold only letters, digits and . _ - +; rename it"), std::string::npos)
        << slurp(copies + "-odd.log");
    EXPECT_FALSE(std::filesystem::exists(copies + "/odd/pointing_error.csv")) << name;
  }
}

}  // namespace
