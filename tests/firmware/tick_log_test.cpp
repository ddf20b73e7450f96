// firmware_sim's --tick-log table (firmware_sim/programs/tick_log.hpp): the loop
// thread's add() allocates nothing, the rows written are the ticks added, in
// microseconds with every nanosecond digit, and the table refuses what it
// cannot hold before the run starts.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "alloc_guard.hpp"
#include "tick_log.hpp"

namespace gimbalsim::firmware {
namespace {

std::string tempPath(const char* name) {
  return (std::filesystem::temp_directory_path() / (std::string("gimbalsim_") + name + "_" + std::to_string(::getpid()) + ".csv")).string();
}

TEST(TickLog, AddingTheReservedTicksAllocatesNothingAndRowsBeyondAreDropped) {
  ASSERT_GE(test::probeAllocations(), 1) << "the counter must see allocations";
  const std::string path = tempPath("ticklog");
  TickLog log;
  std::string why;
  ASSERT_TRUE(log.open(path, 3, {}, &why)) << why;
  const long long before = test::g_allocations.load();
  log.add({50, 200, 1234567, 2000001, 2100000});
  log.add({0, 0, 5, 0, 999});
  log.add({1, 4, spanField(3000000000LL), 7, 8});
  log.add({9, 9, 9, 9, 9});  // a fourth: beyond the table, dropped
  EXPECT_EQ(test::g_allocations.load() - before, 0) << "heap allocations in the loop's add()";
  ASSERT_TRUE(log.writeRows(&why)) << why;
  ASSERT_TRUE(log.file()->commit()) << log.file()->error();
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text,
            "tick,substeps,derivatives,stepping_cpu_us,compute_cpu_us,compute_wall_us\n"
            "0,50,200,1234.567,2000.001,2100.000\n"
            "1,0,0,0.005,0.000,0.999\n"
            "2,1,4,2147483.647,0.007,0.008\n");
  std::filesystem::remove(path);
}

TEST(TickLog, RefusesAnUnboundedRunAndOneLongerThanItHolds) {
  const std::string path = tempPath("ticklog_refused");
  std::string why;
  TickLog unbounded;
  EXPECT_FALSE(unbounded.open(path, -1, {}, &why));
  EXPECT_NE(why.find("needs a bounded run (--duration > 0)"), std::string::npos) << why;
  TickLog too_long;
  EXPECT_FALSE(too_long.open(path, TickLog::kMaxTicks + 1, {}, &why));
  EXPECT_NE(why.find("2000001 ticks asked; it holds at most 2000000"), std::string::npos) << why;
  EXPECT_EQ(unbounded.file(), nullptr);
  EXPECT_FALSE(std::filesystem::exists(path)) << "a refused log creates nothing";
}

}  // namespace
}  // namespace gimbalsim::firmware
