// The plant keeps ticking whatever arrives on the network (issue 13). The
// real firmware_sim, pointing_controller and gimbalsim_record over udpm in a
// private network namespace, while hil_attack puts on the bench's group a
// fragment flood (fragment 0s that never complete, from 8 ports, orphans,
// unsubscribed channels, 4 GB declarations), every kind of malformed
// datagram (among them the short fragment that crashes LCM 1.3.1's receive
// thread), spoofed commands from another source with seq INT64_MAX and
// with the controller's next seq, and spoofed statuses for the controller.
//  - Lockstep: the attacked bench's truth equals a clean bench's run side by
//    side, bit for bit, except the COMMAND_REJECTED flag of the ticks that
//    rejected a spoof; no lockstep timeout, no watchdog trip; every spoof
//    counted as "from another source"; the recorder's log converts and its
//    truth equals firmware_sim's.
//  - Real time: the watchdog never trips, the plant exits 0 (the controller
//    6: no peer once the plant has ended).
//  - A stranger that commands the plant before the controller starts holds
//    it (and leaves INT64_MAX as the plant's last accepted seq) only until
//    its binding lapses; then the controller takes the plant and keeps it.
//  - Memory: each process's peak RSS (VmHWM, from its own exit summary) stays
//    under kMaxRssKb and within kMaxGrowthKb of the clean run's.
#include <gtest/gtest.h>

#include <limits>
#include <regex>
#include <string>

#include "hil_util.hpp"

namespace gimbalsim::hil {
namespace {

constexpr int kCommandRejected = 4;  // gimbal_status_t::FAULT_COMMAND_REJECTED
#ifdef GIMBALSIM_SANITIZED
// ASan's shadow memory and quarantine (freed blocks held back, by design) are
// not the program's and add 40-70 MB whatever arrives: the absolute bound is
// the normal build's; the growth against the clean run is checked in both.
constexpr long kMaxRssKb = std::numeric_limits<long>::max();
#else
constexpr long kMaxRssKb = 48 * 1024;   // the stated bound (measured: 7-21 MB)
#endif
constexpr long kMaxGrowthKb = 2 * 1024; // attacked minus clean

std::string attacker(int port, double pps) {
  return "'" + std::string(GIMBALSIM_HIL_ATTACK) + "' --lcm-url '" + udpmUrl(port) + "' --seconds 30 --idle-exit 1 " +
         "--flood-pps " + std::to_string(static_cast<long>(pps)) + " --malformed-every-ms 20 --spoof-every-ms 10";
}

long long number(const std::string& text, const std::string& re) {
  std::smatch m;
  if (!std::regex_search(text, m, std::regex(re))) return -1;
  return std::stoll(m[1]);
}

long peakKb(const std::string& log) { return static_cast<long>(number(log, "VmHWM\\) (\\d+) kB")); }

TEST(HilAttack, LockstepRunUnderAttackEqualsACleanRun) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("attack_lockstep");
  const std::string cfg = defaultControllerConfig();
  auto bench = [&](int port, const std::string& name) {
    const std::string url = udpmUrl(port);
    return "timeout 60 " + pointingController() + " " + cfg + " --lcm-url '" + url +
           "' --duration 3 --idle-exit 5 >" + name + ".ctl 2>&1 &\n" + "timeout 60 " + firmwareSim() + " " +
           scenePath("paper_clearance") + " --lockstep --duration 3 --profile " + cfg + " --truth-csv " + name +
           ".csv --lcm-url '" + url + "' --start-timeout 10 >" + name + ".log 2>&1";
  };
  const std::string body =
      attacker(7761, 20000) + " >attack.log 2>&1 &\nA=$!\n'" + std::string(GIMBALSIM_RECORD) + "' --lcm-url '" +
      udpmUrl(7761) + "' --duration 30 rec.lcmlog 2>rec.log &\nR=$!\nsleep 0.2\n" + bench(7751, "clean") +
      " &\nC=$!\n" + bench(7761, "attacked") +
      "\nra=$?; wait $C; rc=$?; wait $A; rk=$?; kill -TERM $R; wait $R; rr=$?; wait\n"
      "echo \"rc $rc ra $ra rk $rk rr $rr\"\n[ $rc -eq 0 ] && [ $ra -eq 0 ] && [ $rk -eq 0 ] && [ $rr -eq 143 ]";  // recorder: SIGTERM
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "attack.log")
                                      << readFile(dir / "attacked.log") << readFile(dir / "rec.log");
  const std::string attack = readFile(dir / "attack.log"), fw = readFile(dir / "attacked.log");
  std::printf("%s%s%s", attack.c_str(), fw.c_str(), readFile(dir / "rec.log").c_str());
  const long long spoofs = number(attack, "(\\d+) spoofed commands");
  const long long flood = number(attack, "flood (\\d+) datagrams");
  ASSERT_GT(spoofs, 10) << attack;
  EXPECT_GT(flood, 2000) << "the flood ran while the benches did";

  // (The attacker goes on a little after the plant's end: the plant counts what it received.)
  const auto clean = summaryCounters(readFile(dir / "clean.log"));
  const auto bad = summaryCounters(fw);
  const long long rejected = bad.at("rejected");
  EXPECT_EQ(clean.at("rejected"), 0);
  EXPECT_GT(rejected, 0) << "spoofs reached the plant";
  EXPECT_LE(rejected, spoofs);
  EXPECT_EQ(bad.at("reason: from another source than the bound controller"), rejected) << "spoofs, and nothing else";
  EXPECT_EQ(bad.at("received"), clean.at("received") + rejected) << "no command of the controller lost";
  // The controller ignored the spoofed statuses (else it would have restarted on the next real one).
  const std::string ctl = readFile(dir / "attacked.ctl");
  EXPECT_GT(number(ctl, "(\\d+) from another source than the plant"), 0) << ctl;
  EXPECT_EQ(number(ctl, "(\\d+) plant restarts"), 0) << ctl;
  EXPECT_EQ(number(ctl, "(\\d+) rebinds to another plant source"), 0) << "a living plant never loses it: " << ctl;
  EXPECT_EQ(bad.at("missed"), clean.at("missed"));
  EXPECT_EQ(bad.at("watchdog_trips"), 0);
  EXPECT_EQ(bad.at("lockstep_timeouts"), 0);
  EXPECT_GT(number(fw, "dropped (\\d+)"), 0) << "the receiver saw and dropped the attack";

  const Csv a = Csv::read(dir / "clean.csv"), b = Csv::read(dir / "attacked.csv");
  ASSERT_EQ(a.header, b.header);
  ASSERT_EQ(a.rows.size(), 3001u);  // t = 0 .. 3 s
  ASSERT_EQ(b.rows.size(), a.rows.size());
  const int c_f = a.col("faults");
  int differing = 0, flagged = 0;
  for (size_t k = 0; k < a.rows.size(); ++k) {
    for (size_t j = 0; j < a.rows[k].size(); ++j) {
      if (static_cast<int>(j) != c_f && a.rows[k][j] != b.rows[k][j] && ++differing <= 3) {
        ADD_FAILURE() << "tick " << k << " column " << a.header[j] << ": clean " << a.rows[k][j] << ", attacked "
                      << b.rows[k][j];
      }
    }
    EXPECT_EQ(b.integer(k, c_f) & ~kCommandRejected, a.integer(k, c_f)) << "tick " << k;
    flagged += (b.integer(k, c_f) & kCommandRejected) != 0;
  }
  EXPECT_EQ(differing, 0);
  // A tick that rejected spoofs is flagged (one tick can take several pairs).
  EXPECT_GE(flagged, 1);
  EXPECT_LE(flagged, rejected);
  EXPECT_GT(a.num(2999, a.col("theta1_rad")), 0.1) << "the slew was under way";

  // Memory: bounded, and no growth under attack.
  const long clean_kb = peakKb(readFile(dir / "clean.log")), bad_kb = peakKb(fw);
  const long ctl_clean = peakKb(readFile(dir / "clean.ctl")), ctl_bad = peakKb(readFile(dir / "attacked.ctl"));
  const long rec_kb = peakKb(readFile(dir / "rec.log"));
  ASSERT_GT(clean_kb, 0);
  EXPECT_LT(bad_kb, kMaxRssKb);
  EXPECT_LT(bad_kb - clean_kb, kMaxGrowthKb) << "firmware_sim clean " << clean_kb << " kB, attacked " << bad_kb;
  EXPECT_LT(ctl_bad, kMaxRssKb);
  EXPECT_LT(ctl_bad - ctl_clean, kMaxGrowthKb) << "controller clean " << ctl_clean << " kB, attacked " << ctl_bad;
  EXPECT_GT(rec_kb, 0);
  EXPECT_LT(rec_kb, kMaxRssKb);

  // The recorder survived the same traffic and its log is the run: every
  // truth row it holds is firmware_sim's, in order; a row it lacks was lost
  // in the kernel (socket buffer full while it was off the CPU) and counted
  // as such, never silently.
  int st = 0;
  const std::string conv = runCapture("'" + std::string(GIMBALSIM_LOG2CSV) + "' '" + (dir / "rec.lcmlog") +
                                          "' --channel GIMBAL_TRUTH --out '" + (dir / "rec_truth.csv") + "'",
                                      &st);
  ASSERT_EQ(st, 0) << conv;
  const Csv r = Csv::read(dir / "rec_truth.csv");
  ASSERT_EQ(r.header, b.header);
  size_t k = 0;
  for (const auto& row : r.rows) {
    while (k < b.rows.size() && b.rows[k] != row) ++k;
    ASSERT_LT(k, b.rows.size()) << "a recorded truth row that firmware_sim did not write, or out of order";
  }
  const long long kernel_lost = number(readFile(dir / "rec.log"), "(\\d+) lost in the kernel");
  std::printf("recorder: %zu of %zu truth rows, %lld datagrams lost in the kernel\n", r.rows.size(), b.rows.size(),
              kernel_lost);
  if (r.rows.size() < b.rows.size()) {
    EXPECT_GT(kernel_lost, 0) << "truth rows missing from the log, uncounted";
  }
}

TEST(HilAttack, RealTimePlantKeepsItsControllerUnderFlood) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("attack_realtime");
  const std::string cfg = defaultControllerConfig(), url = udpmUrl(7771);
  const double flood_pps = 50000;  // the rate stated in the README as sustained
  // The controller is up before the plant starts (else the watchdog trips at the start, attack or not).
  const std::string body =
      std::string(kStartedFn) + "timeout 30 " + pointingController() + " " + cfg + " --lcm-url '" + url +
      "' --duration 1.5 --idle-exit 1 >ctl.log 2>&1 &\nC=$!\nstarted ctl.log 'pointing_controller: GIMBAL_STATUS' || exit 90\n" +
      attacker(7771, flood_pps) + " >attack.log 2>&1 &\nA=$!\n" + "timeout 30 " +
      firmwareSim() + " " + scenePath("paper_clearance") + " --duration 1.5 --profile " + cfg +
      " --truth-csv truth.csv --lcm-url '" + url + "' >fw.log 2>&1\nrf=$?; wait $C; rc=$?; wait $A; ra=$?; wait\n"
      "echo \"rf $rf rc $rc ra $ra\"\n[ $rf -eq 0 ] && [ $rc -eq 0 ] && [ $ra -eq 0 ]";  // controller: ends with the plant's last status (0)
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "fw.log")
                                      << readFile(dir / "ctl.log") << readFile(dir / "attack.log");
  const std::string attack = readFile(dir / "attack.log"), fw = readFile(dir / "fw.log");
  std::printf("%s%s", attack.c_str(), fw.c_str());
  const long long spoofs = number(attack, "(\\d+) spoofed commands");
  const auto n = summaryCounters(fw);
  EXPECT_EQ(n.at("watchdog_trips"), 0) << fw;
  EXPECT_GT(n.at("rejected"), 0) << "spoofs reached the plant";
  EXPECT_LE(n.at("rejected"), spoofs);
  EXPECT_EQ(n.at("reason: from another source than the bound controller"), n.at("rejected")) << "only spoofs";
  // The controller's commands arrive: 1499 statuses need an answer. Alone on
  // the machine every one arrived (README); a loaded machine may delay the
  // last few past the plant's end, so the test asks for 98 %.
  EXPECT_GE(n.at("received") - n.at("rejected"), 1469) << "commands of the controller lost under the flood";
  EXPECT_GT(number(attack, "flood (\\d+) datagrams"), static_cast<long long>(0.5 * flood_pps)) << attack;
  const Csv c = Csv::read(dir / "truth.csv");
  ASSERT_EQ(c.rows.size(), 1501u) << "the plant kept ticking";  // t = 0 .. 1.5 s
  for (size_t k = 0; k < c.rows.size(); ++k) {
    ASSERT_EQ(c.integer(k, c.col("seq")), static_cast<long long>(k));
    ASSERT_EQ(c.integer(k, c.col("faults")) & 1, 0) << "watchdog tripped at tick " << k;
  }
  EXPECT_LT(peakKb(fw), kMaxRssKb);
}

TEST(HilAttack, RealTimeStrangerThatCommandsFirstLosesThePlantWhenItsBindingLapses) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("attack_first");
  const std::string cfg = defaultControllerConfig(), url = udpmUrl(7781);
  // No flood: the stranger spoofs every 10 ms from the plant's first status
  // on; the controller joins 0.4 s later, while every status says
  // last_command_seq INT64_MAX.
  const std::string body =
      "'" + std::string(GIMBALSIM_HIL_ATTACK) + "' --lcm-url '" + url +
      "' --seconds 30 --idle-exit 1 --spoof-every-ms 10 --spoof-at-once >attack.log 2>&1 &\nA=$!\nsleep 0.2\n" +
      "timeout 30 " + firmwareSim() + " " + scenePath("paper_clearance") + " --duration 1.6 --profile " + cfg +
      " --truth-csv truth.csv --lcm-url '" + url + "' >fw.log 2>&1 &\nF=$!\nsleep 0.4\n" + "timeout 30 " +
      pointingController() + " " + cfg + " --lcm-url '" + url + "' --duration 1.6 --idle-exit 1 >ctl.log 2>&1 &\n" +
      "C=$!\nwait $F; rf=$?; wait $C; rc=$?; wait $A; ra=$?\necho \"rf $rf rc $rc ra $ra\"\n"
      "[ $rf -eq 0 ] && [ $rc -eq 0 ] && [ $ra -eq 0 ]";
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "fw.log")
                                      << readFile(dir / "ctl.log") << readFile(dir / "attack.log");
  const std::string fw = readFile(dir / "fw.log"), ctl = readFile(dir / "ctl.log");
  std::printf("%s%s%s", readFile(dir / "attack.log").c_str(), fw.c_str(), ctl.c_str());
  const auto n = summaryCounters(fw);
  auto count = [&](const std::string& key) { return n.count(key) ? n.at(key) : 0; };
  const long long stale = count("reason: stale or duplicate seq");
  const long long foreign = count("reason: from another source than the bound controller");
  // Stale refusals come from the bound source only, and the controller's seq
  // only rises: they are the stranger's second spoofs while it held the plant.
  EXPECT_GT(stale, 0) << "the stranger never held the plant: the test proves nothing";
  EXPECT_GT(foreign, 0) << "the controller or the stranger was refused as the other's source";
  EXPECT_EQ(stale + foreign, count("rejected")) << "no other refusal";
  EXPECT_EQ(number(ctl, "(\\d+) plant restarts"), 0) << "the stranger's statuses never reset the controller";
  // The controller binds to the first source it hears, the plant or (a race the stranger wins now and then:
  // CI on pass 78's fixes) a spoof, provisionally until two of the plant's statuses in a row show its stream;
  // another's status takes a provisional binding. One spoof per 10 ms against a status per 1 ms: at most
  // one spoof lands before the plant's stream shows, so at most 3 rebinds (plant, stranger, plant).
  EXPECT_LE(number(ctl, "(\\d+) rebinds to another plant source"), 3) << ctl;

  const Csv c = Csv::read(dir / "truth.csv");
  ASSERT_EQ(c.rows.size(), 1601u);  // t = 0 .. 1.6 s
  const int c_f = c.col("faults");
  long long last_tripped = -1;
  for (size_t k = 0; k < c.rows.size(); ++k) {
    if (c.integer(k, c_f) & 1) last_tripped = static_cast<long long>(k);
  }
  std::printf("watchdog trips %lld, last tripped tick %lld\n", count("watchdog_trips"), last_tripped);
  EXPECT_GE(last_tripped, 0) << "the plant ran unattended by its controller at first";
  // The controller joined after about 0.4-0.6 s; one lapse later it holds the
  // plant. A controller that followed last_command_seq would send INT64_MAX
  // for good and trip the watchdog every 51 ticks to the end.
  EXPECT_LT(last_tripped, 1100) << "the controller did not keep the plant for the last 0.5 s";
}

}  // namespace
}  // namespace gimbalsim::hil
