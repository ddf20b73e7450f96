// firmware_sim in real time keeps wall-clock time (README "Wall-clock time"):
// a scene whose every tick computes longer than the period (paper_ideal with
// a 0.25 us RK4 step: 4000 steps per 1 ms tick, about 3.5 ms of work here, so
// that a machine three times faster still overruns) overruns on every tick; the
// plant still advances through every period, each with its truth and status,
// stamped with its own deadline, and the summary counts the late ticks. The
// worst-case tick bound is stated at start and the warning names the keys.
// memq:// (no network), SCHED_OTHER (no privileges needed).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <filesystem>
#include <regex>
#include <string>

#include "csv_util.hpp"
#include "test_util.hpp"

namespace gimbalsim::firmware {
namespace {

std::string runCapture(const std::string& cmd, int* status) {
  std::string out;
  if (std::FILE* p = ::popen((cmd + " 2>&1").c_str(), "r")) {
    char buf[512];
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    *status = ::pclose(p);
  }
  return out;
}

TEST(WallClock, OverrunTicksCatchUpWithOneTruthPerPeriodStampedWithItsDeadline) {
  const std::string csv = (std::filesystem::temp_directory_path() / ("gimbalsim_wallclock_" + std::to_string(::getpid()) + ".csv")).string();
  int st = 0;
  const std::string out = runCapture(std::string(GIMBALSIM_FIRMWARE_SIM) + " " + test::scenePath("paper_ideal") +
                                         " --duration 0.2 --lcm-url memq:// --rt-priority 0 --set sim.step=2.5e-7"
                                         " --set sim.substep=2.5e-7 --truth-csv " + csv,
                                     &st);
  ASSERT_EQ(st, 0) << out;
  EXPECT_NE(out.find("worst-case tick"), std::string::npos) << out;
  EXPECT_NE(out.find("exceeds the control period (1000 us): every tick overruns; lengthen sim.step"), std::string::npos) << out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(out, m, std::regex("late ticks (\\d+)"))) << out;
  const long long late = std::stoll(m[1]);
  EXPECT_GE(late, 100) << "every tick computes ~3.5 ms against a 1 ms period: nearly all start late\n" << out;
  EXPECT_LE(late, 199) << "tick 0 starts on time";
  EXPECT_NE(out.find("firmware_sim: 200 ticks, 0.200 s simulated"), std::string::npos) << out;

  const test::Csv c = test::Csv::read(csv);
  // t = 0 .. 0.2 s: the last row, the plant at the end, stamped with its deadline as well.
  ASSERT_EQ(c.rows.size(), 201u) << "one truth per period, none skipped";
  const int c_seq = c.col("seq"), c_t = c.col("sim_time_s"), c_u = c.col("utime_us");
  const long long u0 = c.integer(0, c_u);
  for (std::size_t k = 0; k < c.rows.size(); ++k) {
    ASSERT_EQ(c.integer(k, c_seq), static_cast<long long>(k));
    // The plant's time is a sum of 4000 k steps of 0.25 us: its round-off is
    // at most one ulp of the time per step, far below the period.
    const double roundoff = 4000.0 * k * std::numeric_limits<double>::epsilon() * (k * 1e-3);
    ASSERT_NEAR(c.num(k, c_t), k * 1e-3, roundoff + 1e-15) << "simulated time is the period grid";
    ASSERT_EQ(c.integer(k, c_u) - u0, static_cast<long long>(k) * 1000) << "stamped with its own deadline, tick " << k;
  }
  std::filesystem::remove(csv);
}

/// The summary's "<label> [us]: p50 A  p99 B  max C" figures, or NaNs.
std::array<double, 3> computeLine(const std::string& out, const std::string& label) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex(label + " \\[us\\]: p50 (\\S+)  p99 (\\S+)  max (\\S+)"))) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return {nan, nan, nan};
  }
  return {std::stod(m[1]), std::stod(m[2]), std::stod(m[3])};
}

// Each tick's compute is reported in wall time and in the loop thread's CPU
// time over the same span, read inside it: per tick the CPU time cannot
// exceed the wall time (a process-wide clock, which also counts the
// communication thread, could), and it is not zero. The stepping's CPU time
// (what the worst-case bound bounds) lies inside the tick's.
TEST(WallClock, ComputePerTickInThreadCpuTimeLiesWithinItsWallTime) {
  int st = 0;
  const std::string out = runCapture(std::string(GIMBALSIM_FIRMWARE_SIM) + " " + test::scenePath("paper_clearance") +
                                         " --duration 0.3 --lcm-url memq:// --rt-priority 0",
                                     &st);
  ASSERT_EQ(st, 0) << out;
  const auto wall = computeLine(out, "compute per tick");
  const auto cpu = computeLine(out, "compute per tick, thread CPU");
  ASSERT_TRUE(std::isfinite(wall[2]) && std::isfinite(cpu[2])) << out;
  EXPECT_GT(cpu[2], 0.0) << out;
  // 1 us: the bins of the quantiles, and the two clocks' sources may differ by parts per million.
  EXPECT_LE(cpu[0], wall[0] + 1.0) << out;
  EXPECT_LE(cpu[1], wall[1] + 1.0) << out;
  EXPECT_LE(cpu[2], wall[2] + 1.0) << out;
  // The stepping's span lies inside the tick's CPU span.
  const auto stepping = computeLine(out, "stepping per tick, thread CPU");
  ASSERT_TRUE(std::isfinite(stepping[2])) << out;
  EXPECT_GT(stepping[2], 0.0) << out;
  EXPECT_LE(stepping[0], cpu[0] + 1.0) << out;
  EXPECT_LE(stepping[1], cpu[1] + 1.0) << out;
  EXPECT_LE(stepping[2], cpu[2] + 1.0) << out;
  EXPECT_NE(out.find("; worst-case bound"), std::string::npos) << out;
}

// --tick-log holds every tick, and its figures are the ones the summary's
// statistics were built from: the longest stepping and the most derivatives.
// Per tick the spans nest: stepping <= the tick's CPU time <= its wall time.
TEST(WallClock, TickLogHasEveryTickAndAgreesWithTheSummary) {
  const std::string log = (std::filesystem::temp_directory_path() / ("gimbalsim_ticklog_" + std::to_string(::getpid()) + ".csv")).string();
  int st = 0;
  const std::string out = runCapture(std::string(GIMBALSIM_FIRMWARE_SIM) + " " + test::scenePath("paper_clearance") +
                                         " --duration 0.3 --lcm-url memq:// --rt-priority 0 --watchdog-ms 1 --safe-torque 5 10 --tick-log " + log,
                                     &st);
  ASSERT_EQ(st, 0) << out;
  const test::Csv c = test::Csv::read(log);
  ASSERT_EQ(c.rows.size(), 300u) << "one row per tick";
  const int c_tick = c.col("tick"), c_sub = c.col("substeps"), c_der = c.col("derivatives"),
            c_step = c.col("stepping_cpu_us"), c_cpu = c.col("compute_cpu_us"), c_wall = c.col("compute_wall_us");
  double step_max = 0.0;
  long long der_max = 0, substeps = 0;
  for (std::size_t k = 0; k < c.rows.size(); ++k) {
    ASSERT_EQ(c.integer(k, c_tick), static_cast<long long>(k));
    EXPECT_EQ(c.integer(k, c_der) > 0, c.integer(k, c_sub) > 0) << "tick " << k;
    EXPECT_LE(c.num(k, c_step), c.num(k, c_cpu)) << "tick " << k;
    EXPECT_LE(c.num(k, c_cpu), c.num(k, c_wall) + 1.0) << "tick " << k;  // two clocks: 1 us
    step_max = std::max(step_max, c.num(k, c_step));
    der_max = std::max(der_max, c.integer(k, c_der));
    substeps += c.integer(k, c_sub);
  }
  EXPECT_GT(substeps, 300) << "the safe torque drives the joint into its bearing: sub-steps in contact";
  const auto stepping = computeLine(out, "stepping per tick, thread CPU");
  EXPECT_NEAR(step_max, stepping[2], 0.05 + 1e-9) << out;  // the summary prints 0.1 us
  std::smatch m;
  ASSERT_TRUE(std::regex_search(out, m, std::regex("derivative evaluations: max (\\d+) of the bound's (\\d+)"))) << out;
  EXPECT_EQ(der_max, std::stoll(m[1])) << out;
  EXPECT_LE(der_max, std::stoll(m[2])) << "every tick's count within the bound's";
  std::filesystem::remove(log);
}

}  // namespace
}  // namespace gimbalsim::firmware
