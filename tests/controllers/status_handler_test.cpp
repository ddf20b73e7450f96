// pointing_controller's status handler (controllers/programs/status_handler.hpp): the tracking figure of its
// summary is over accepted readings only. A lone rejected reading (an Inf angle) while tracking printed
// "max |joint error| while tracking 0.000e+00 rad" (pass 63): a figure over nothing.
#include <gtest/gtest.h>

#include <cerrno>
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

// --log-csv: a rejected reading's cells are nan with the reason beside them, never inf (pass 63: bare nan,
// inf and -inf cells, which the CSV convention has no place for).
TEST(StatusHandler, TheLogWritesNanWithItsReasonNeverInf) {
  const ControllerConfig c = loadControllerConfig(test::defaultControllerConfig());
  lcm_wire::UdpmSender tx;
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  StatusHandler::header(f);
  StatusHandler h(c, tx, contract::Channels::withPrefix(""), f);
  for (const auto& [seq, az] : std::vector<std::pair<long long, double>>{
           {0, 0.0}, {1, std::numeric_limits<double>::infinity()}, {2, 1e308}, {3, 0.0}}) {
    const std::vector<std::uint8_t> b = status(seq, az);
    h.onStatus(b.data(), static_cast<int>(b.size()));
  }
  std::rewind(f);
  std::vector<std::string> lines;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, f)) lines.emplace_back(buf);
  std::fclose(f);
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

// A --log-csv row that cannot be written keeps the system's reason (pass 66: "write failed" alone on a full disk).
TEST(StatusHandler, AFailedLogRowKeepsTheSystemsReason) {
  const ControllerConfig c = loadControllerConfig(test::defaultControllerConfig());
  lcm_wire::UdpmSender tx;
  std::FILE* f = std::fopen("/dev/full", "w");  // every write that reaches it: ENOSPC
  ASSERT_NE(f, nullptr);
  std::setvbuf(f, nullptr, _IONBF, 0);
  StatusHandler h(c, tx, contract::Channels::withPrefix(""), f);
  EXPECT_STREQ(h.logFailure(), "");
  const std::vector<std::uint8_t> b = status(0, 0.0);
  h.onStatus(b.data(), static_cast<int>(b.size()));
  EXPECT_STREQ(h.logFailure(), std::strerror(ENOSPC));
  std::fclose(f);
}

}  // namespace
}  // namespace gimbalsim::controllers
