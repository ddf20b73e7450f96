// pointing_controller's status handler (controllers/programs/status_handler.hpp): the tracking figure of its
// summary is over accepted readings only. A lone rejected reading (an Inf angle) while tracking printed
// "max |joint error| while tracking 0.000e+00 rad" (pass 63): a figure over nothing.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <cerrno>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "gimbalsim/contract/channels.hpp"
#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/gimbal_status_t.hpp"
#include "gimbalsim/io/output_file.hpp"
#include "gimbalsim/lcm_wire/udpm_sender.hpp"
#include "status_handler.hpp"
#include "test_util.hpp"

namespace gimbalsim::controllers {
namespace {

std::vector<std::uint8_t> status(long long seq, double az) {
  gimbal_status_t st{};
  st.utime = seq * 1000;
  st.seq = seq;
  st.angle[0] = az;
  st.last_command_seq = -1;
  std::vector<std::uint8_t> b(static_cast<size_t>(st.getEncodedSize()));
  st.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

TEST(StatusHandler, TheTrackingFigureIsOverAcceptedReadingsOnly) {
  const ControllerConfig c = loadControllerConfig(test::defaultControllerConfig());
  lcm_wire::UdpmSender tx;  // never opened: each answer counts as a publish error, which is not under test
  StatusHandler h(c, tx, contract::Channels::withPrefix(""), nullptr);
  auto feed = [&h](long long seq, double az) {
    const std::vector<std::uint8_t> b = status(seq, az);
    h.onStatus(b.data(), static_cast<int>(b.size()));
  };
  feed(0, 0.0);
  feed(4000, std::numeric_limits<double>::infinity());  // t = 4 s: tracking, the reading rejected
  EXPECT_EQ(h.trackStatuses(), 1);
  EXPECT_EQ(h.rejectedReadings(), 1);
  EXPECT_TRUE(std::isnan(h.maxTrackError())) << h.maxTrackError();
  feed(4001, 1.0);  // an accepted reading there: a figure, the joint error of that reading
  EXPECT_GT(h.maxTrackError(), 0.4);
  EXPECT_EQ(h.trackStatuses(), 2);
}

// The --log-csv file, read back whole after its commit.
std::vector<std::string> committedLines(io::OutputFile& log) {
  EXPECT_TRUE(log.commit()) << log.error();
  std::vector<std::string> lines;
  std::FILE* f = std::fopen(log.path().c_str(), "r");
  if (f == nullptr) return lines;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, f)) lines.emplace_back(buf);
  std::fclose(f);
  std::remove(log.path().c_str());
  return lines;
}

// --log-csv: a rejected reading's cells are nan with the reason beside them, never inf (pass 63: bare nan,
// inf and -inf cells, which the CSV convention has no place for).
TEST(StatusHandler, TheLogWritesNanWithItsReasonNeverInf) {
  const ControllerConfig c = loadControllerConfig(test::defaultControllerConfig());
  lcm_wire::UdpmSender tx;
  io::OutputFile log(::testing::TempDir() + "status_handler_log.csv");
  log.write(StatusHandler::header());
  StatusHandler h(c, tx, contract::Channels::withPrefix(""), &log);
  for (const auto& [seq, az] : std::vector<std::pair<long long, double>>{
           {0, 0.0}, {1, std::numeric_limits<double>::infinity()}, {2, 1e308}, {3, 0.0}}) {
    const std::vector<std::uint8_t> b = status(seq, az);
    h.onStatus(b.data(), static_cast<int>(b.size()));
  }
  const std::vector<std::string> lines = committedLines(log);
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_NE(lines[0].find(",suspect_el,reason\n"), std::string::npos) << lines[0];
  EXPECT_NE(lines[1].find(",\n"), std::string::npos) << "a whole reading has no reason: " << lines[1];
  EXPECT_NE(lines[2].find(",nan,"), std::string::npos) << lines[2];
  EXPECT_NE(lines[2].find(",reading rejected (a NaN or Inf in it): the last command held\n"), std::string::npos)
      << lines[2];
  // 1e308 is finite, but kp x 1e308 overflows the unlimited torque: nan, and why; and no command goes out
  // (its saturated torque was sent at full scale: pass 64)
  EXPECT_NE(lines[3].find(",a value computed from the reading is not finite (an overflow)\n"), std::string::npos)
      << lines[3];
  EXPECT_GE(h.notFinite(), 1);
  for (const std::string& l : lines) EXPECT_EQ(l.find("inf"), std::string::npos) << l;
}

// A --log-csv row that cannot be written keeps the system's reason (pass 66: "write failed" alone on a full
// disk). A file size limit of 0 makes every write that reaches the file fail (EFBIG), as a full disk would.
TEST(StatusHandler, AFailedLogRowKeepsTheSystemsReason) {
  const ControllerConfig c = loadControllerConfig(test::defaultControllerConfig());
  lcm_wire::UdpmSender tx;
  io::OutputFile log(::testing::TempDir() + "status_handler_full.csv");
  StatusHandler h(c, tx, contract::Channels::withPrefix(""), &log);
  rlimit before{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &before), 0);
  void (*old_handler)(int) = std::signal(SIGXFSZ, SIG_IGN);  // the write fails with EFBIG, not the process
  rlimit none = before;
  none.rlim_cur = 0;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &none), 0);
  for (long long seq = 0; seq < 100 && log.ok(); ++seq) {  // rows past the stream's buffer: a write reaches the file
    const std::vector<std::uint8_t> b = status(seq, 0.0);
    h.onStatus(b.data(), static_cast<int>(b.size()));
  }
  ::setrlimit(RLIMIT_FSIZE, &before);
  std::signal(SIGXFSZ, old_handler);
  EXPECT_FALSE(log.ok());
  EXPECT_NE(log.error().find(std::string("write failed: ") + std::strerror(EFBIG)), std::string::npos) << log.error();
}

// ---- The plant it answers (plant_binding.hpp): pass 78 saw a spoofed status that arrived before the plant's
// first one hold the controller for good (a stranger repeating it every 10 ms was never silent 0.5 s).

struct Bus {
  const ControllerConfig c = loadControllerConfig(test::defaultControllerConfig());  // period 1 ms
  lcm_wire::UdpmSender tx;
  contract::Channels ch = contract::Channels::withPrefix("");
  StatusHandler h{c, tx, ch, nullptr};
  void status(lcm_wire::Source from, long long seq, std::int64_t now_ns) {
    const std::vector<std::uint8_t> b = controllers::status(seq, 0.0);
    h.onMessage(lcm_wire::Message{ch.status, b.data(), b.size(), from, false}, now_ns);
  }
};
constexpr lcm_wire::Source kPlant{0x0100007f, 4000}, kStranger{0x0100007f, 5000};
constexpr long long kMaxSeq = std::numeric_limits<std::int64_t>::max();
constexpr std::int64_t kMs = 1000000;

TEST(StatusHandler, AStrangerHeardFirstLosesTheControllerToThePlantsStream) {
  Bus b;
  b.status(kStranger, kMaxSeq, 0);  // first heard: bound, provisionally (no stream shown)
  // Its seq is past a 1.6 s run's last status (1599), but a lone status is no plant's stream: the run goes on
  // (pass 78's CI: the controller answered the spoof, ended its run and left the plant to its watchdog).
  EXPECT_FALSE(b.h.runEnded(1599));
  for (long long k = 1; k <= 100; ++k) {
    b.status(kPlant, 400 + k, k * kMs);
    if (k % 10 == 0) b.status(kStranger, kMaxSeq, k * kMs);  // the spoof repeats every 10 ms
  }
  EXPECT_EQ(b.h.rebinds(), 1) << "the plant's first status took the provisional binding; its second showed it";
  EXPECT_EQ(b.h.lastSeq(), 500) << "the plant's statuses are answered";
  EXPECT_EQ(b.h.plantRestarts(), 0) << "a rebind starts afresh; it is no restart of the plant";
  EXPECT_EQ(b.h.answered(), 1 + 100);  // the first spoof, then every status of the plant
  EXPECT_EQ(b.h.foreign(), 10);        // the spoofs at 10 .. 100 ms
  EXPECT_FALSE(b.h.runEnded(1599));
  EXPECT_TRUE(b.h.runEnded(500)) << "the plant's stream reached the last status";
  EXPECT_TRUE(b.h.runEnded(499)) << "or passed it (the last one lost)";
}

TEST(StatusHandler, AOneStatusRunEndsOnItsOnlyStatus) {
  Bus b;
  b.status(kPlant, 0, 0);
  EXPECT_TRUE(b.h.runEnded(0));
  EXPECT_FALSE(b.h.runEnded(1));
}

TEST(StatusHandler, ALockstepPlantRepeatingStatus0TakesTheControllerFromAStranger) {
  // A lockstep plant repeats status 0 every 200 ms until it is answered; a stranger heard first (and again
  // before the plant's stream shows) must not keep it waiting: the plant's status 0 is answered at once.
  Bus b;
  b.status(kStranger, kMaxSeq, 0);
  b.status(kPlant, 0, 1 * kMs);
  EXPECT_EQ(b.h.lastSeq(), 0) << "status 0 answered";
  b.status(kStranger, kMaxSeq, 2 * kMs);  // a spoof before the plant's answer-driven status 1
  for (long long k = 1; k <= 50; ++k) {
    b.status(kPlant, k, (2 + k) * kMs);
    if (k % 10 == 0) b.status(kStranger, kMaxSeq, (2 + k) * kMs);
  }
  EXPECT_EQ(b.h.lastSeq(), 50);
  EXPECT_EQ(b.h.rebinds(), 3);  // to the plant, to the stranger, back to the plant (its status 1 follows its 0)
  EXPECT_EQ(b.h.foreign(), 5);  // the spoofs once the plant's stream showed
  EXPECT_TRUE(b.h.runEnded(49)) << "the plant's stream has shown";
}

TEST(StatusHandler, ALivingPlantKeepsTheControllerAgainstAStrangersStream) {
  Bus b;
  long long stranger_seq = 0;
  for (long long k = 0; k < 1000; ++k) {
    b.status(kPlant, k, k * kMs);
    if (k < 2) continue;  // the plant's stream has shown (statuses 0 and 1); then a forged stream at 20 kHz
    for (int j = 0; j < 20; ++j) b.status(kStranger, stranger_seq++, k * kMs + j * 40000);
  }
  EXPECT_EQ(b.h.rebinds(), 0);
  EXPECT_EQ(b.h.foreign(), 998 * 20);
  EXPECT_EQ(b.h.lastSeq(), 999);
  EXPECT_EQ(b.h.answered(), 1000);
}

TEST(StatusHandler, ARestartedPlantOnAnotherPortIsTakenOnceItsStreamShows) {
  Bus b;
  for (long long k = 0; k < 50; ++k) b.status(kPlant, k, k * kMs);
  // The plant's process ends; a new one (another port) numbers from 0, 5 ms later.
  for (long long k = 0; k < 100; ++k) b.status(kStranger, k, (55 + k) * kMs);
  EXPECT_EQ(b.h.rebinds(), 1);
  EXPECT_EQ(b.h.lastSeq(), 99);
  // 20 ms after the old plant's last consecutive status (49 ms), with kStreak of the new one: its status 14 at 69 ms
  EXPECT_EQ(b.h.foreign(), 14);
  EXPECT_EQ(b.h.answered(), 50 + 86);
}

}  // namespace
}  // namespace gimbalsim::controllers
