// SIGTERM (and SIGHUP, a closed terminal: pass 70 found it killed the plant with its truth CSV a hidden
// temporary) stops firmware_sim during a run with 128 + N and its summary, also at
// the highest star tracker rate a scene may give (sensors.star_tracker_rate
// = 1e6 Hz, a thousand samples per tick: the sample index jumps, it is not
// counted one by one). The process is bounded by `timeout -s KILL`, so a loop
// that ignores the signal fails the test instead of hanging it.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "test_util.hpp"

namespace gimbalsim::firmware {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Runs firmware_sim until `kill -<sig_name>`; checks the exit code, the summary and the truth CSV.
void stopDuringARun(const std::string& sig_name, int expected_exit) {
  const std::string dir = (std::filesystem::temp_directory_path() /
                           ("gimbalsim_sig" + sig_name + "_" + std::to_string(::getpid()))).string();
  std::filesystem::create_directories(dir);
  const std::string log = dir + "/fw.log", truth = dir + "/truth.csv";
  // Runs until stopped (no --duration); the start line is printed after the handlers are in place.
  const std::string script =
      "timeout -s KILL 30 '" + std::string(GIMBALSIM_FIRMWARE_SIM) + "' " + test::scenePath("paper_ideal") +
      " --set sensors.star_tracker_rate=1e6 --lcm-url memq:// --rt-priority 0 --truth-csv " + truth + " >" + log +
      " 2>&1 &\nF=$!\ni=0; until grep -q 'worst-case tick' " + log + "; do i=$((i+1)); [ $i -gt 400 ] && exit 90; "
      "sleep 0.05; done\nsleep 0.3\nkill -" + sig_name + " $F\nwait $F; exit $?";
  const std::string sh = dir + "/run.sh";
  std::ofstream(sh) << script << "\n";
  const int st = std::system(("sh '" + sh + "'").c_str());
  ASSERT_TRUE(WIFEXITED(st)) << slurp(log);
  EXPECT_EQ(WEXITSTATUS(st), expected_exit) << "137 would be timeout's SIGKILL: the loop ignored SIG" << sig_name
                                            << "\n" << slurp(log);
  const std::string out = slurp(log);
  EXPECT_NE(out.find("commands: received"), std::string::npos) << "the exit summary\n" << out;
  EXPECT_NE(out.find("firmware_sim: interrupted by SIG" + sig_name), std::string::npos) << out;  // (pass 72)
  EXPECT_TRUE(std::filesystem::exists(truth)) << "the truth CSV, whole up to the stop";
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    EXPECT_NE(entry.path().filename().string().front(), '.') << "a temporary left: " << entry.path();
  std::filesystem::remove_all(dir);
}

TEST(FirmwareSignal, SigtermDuringARunAtTheHighestStarTrackerRateExits143) { stopDuringARun("TERM", 143); }

TEST(FirmwareSignal, SighupDuringARunExits129WithWholeOutputs) { stopDuringARun("HUP", 129); }

}  // namespace
}  // namespace gimbalsim::firmware
