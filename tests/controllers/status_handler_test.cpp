// pointing_controller's status handler (controllers/programs/status_handler.hpp): the tracking figure of its
// summary is over accepted readings only. A lone rejected reading (an Inf angle) while tracking printed
// "max |joint error| while tracking 0.000e+00 rad" (pass 63): a figure over nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
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

}  // namespace
}  // namespace gimbalsim::controllers
