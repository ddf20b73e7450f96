// Garbage bytes and wrong-type messages on the command channel of a running
// firmware_sim are counted and ignored. Two lockstep benches run side by side
// in one private network namespace (channel prefixes HIL_C_ and HIL_G_); the
// helper hil_publish puts 14 bad messages (random bytes, a gimbal_status_t, a
// truncated command, a command with trailing bytes, a gimbal_truth_t, a NaN
// torque, an unknown mode) on HIL_G_GIMBAL_COMMAND, one every 100 ticks
// (the two benches on their own udpm ports).
// The garbage run must count every one as received and rejected, flag each in
// one status/truth (FAULT_COMMAND_REJECTED), and otherwise produce the very
// same truth CSV as the clean run: the plant never saw them.
#include <gtest/gtest.h>

#include <string>

#include "hil_util.hpp"

namespace gimbalsim::hil {
namespace {

constexpr int kCommandRejected = 4;  // gimbal_status_t::FAULT_COMMAND_REJECTED

TEST(HilGarbage, BadMessagesOnCommandChannelAreCountedAndIgnored) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("garbage");
  const int n_bad = 14;  // two cycles of hil_publish's 7 kinds
  // One udpm port per bench (see hil_lockstep_test: a shared port can drop packets under load).
  const std::string cfg = defaultControllerConfig();
  auto bench = [&](const std::string& prefix, const std::string& name) {
    const std::string url = udpmUrl(prefix == "HIL_G_" ? 7734 : 7744);
    return "timeout 60 " + pointingController() + " " + cfg + " --lcm-url '" + url + "' --channel-prefix " + prefix +
           " --duration 2 --idle-exit 5 >" + name + ".ctl 2>&1 &\n" + "timeout 60 " + firmwareSim() + " " +
           scenePath("paper_clearance") + " --lockstep --duration 2 --profile " + cfg + " --truth-csv " + name +
           ".csv --lcm-url '" + url + "' --channel-prefix " + prefix + " --start-timeout 10 >" + name +
           ".log 2>&1";
  };
  const std::string body = "timeout 60 '" + std::string(GIMBALSIM_HIL_PUBLISH) + "' --lcm-url '" + udpmUrl(7734) +
                           "' --channel-prefix HIL_G_ --count " + std::to_string(n_bad) +
                           " --every 100 --offset 50 --timeout 30 >pub.log 2>&1 &\nP=$!\n" + bench("HIL_C_", "clean") +
                           " &\nC=$!\n" + bench("HIL_G_", "garbage") +
                           "\nrg=$?; wait $C; rc=$?; wait $P; rp=$?; wait\necho \"rc $rc rg $rg rp $rp\"\n"
                           "[ $rc -eq 0 ] && [ $rg -eq 0 ] && [ $rp -eq 0 ]";
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "pub.log")
                                      << readFile(dir / "garbage.log");

  // Counted: every bad message is received and rejected, by the right reason.
  const auto clean = summaryCounters(readFile(dir / "clean.log"));
  const auto bad = summaryCounters(readFile(dir / "garbage.log"));
  EXPECT_EQ(clean.at("rejected"), 0);
  EXPECT_EQ(bad.at("received"), clean.at("received") + n_bad);
  EXPECT_EQ(bad.at("rejected"), n_bad);
  EXPECT_EQ(bad.at("reason: undecodable bytes (not a gimbal_command_t)"), 10);
  EXPECT_EQ(bad.at("reason: NaN or Inf torque"), 2);
  EXPECT_EQ(bad.at("reason: unknown mode"), 2);
  EXPECT_EQ(bad.at("missed"), clean.at("missed"));
  EXPECT_EQ(bad.at("lockstep_timeouts"), 0);

  // Ignored: the truth is the clean run's, bit for bit, except the flag.
  const Csv a = Csv::read(dir / "clean.csv"), b = Csv::read(dir / "garbage.csv");
  ASSERT_EQ(a.header, b.header);
  ASSERT_EQ(a.rows.size(), 2001u);  // t = 0 .. 2 s
  ASSERT_EQ(b.rows.size(), a.rows.size());
  const int c_f = a.col("faults");
  int flagged = 0, differing = 0;
  for (size_t k = 0; k < a.rows.size(); ++k) {
    ASSERT_EQ(a.rows[k].size(), b.rows[k].size());
    for (size_t j = 0; j < a.rows[k].size(); ++j) {
      if (static_cast<int>(j) == c_f) continue;
      if (a.rows[k][j] != b.rows[k][j] && ++differing <= 3) {
        ADD_FAILURE() << "tick " << k << " column " << a.header[j] << ": clean " << a.rows[k][j] << ", garbage "
                      << b.rows[k][j];
      }
    }
    const long long fa = a.integer(k, c_f), fb = b.integer(k, c_f);
    EXPECT_EQ(fa, 0) << "clean run, tick " << k;
    EXPECT_EQ(fb & ~kCommandRejected, fa) << "garbage run, tick " << k << ": a flag other than COMMAND_REJECTED";
    if (fb & kCommandRejected) ++flagged;
  }
  EXPECT_EQ(differing, 0);
  EXPECT_EQ(flagged, n_bad) << "one flagged tick per bad message (they are 100 ticks apart)";
  EXPECT_GT(a.num(1999, a.col("theta1_rad")), 0.1) << "the slew was under way";
}

}  // namespace
}  // namespace gimbalsim::hil
