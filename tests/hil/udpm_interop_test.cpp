// Our receiver against liblcm's own sender: what lcm_publish puts on the
// wire (a short message, and a 200 kB message that LCM cuts into LC03
// fragments) arrives through lcm_wire::UdpmReceiver byte for byte, and a
// channel the receiver does not subscribe to never reaches it: the kernel's
// socket filter drops it (names sharing a prefix included), while a non-LCM
// datagram still comes up to be counted; a busy-polling wait sees a
// message that arrives during its spin. And the other way: what our sender
// (lcm_wire::UdpmSender, a batch in one system call) puts on the wire,
// liblcm's own receiver hears byte for byte, in order. Runs
// inside a private network namespace: the outer test re-runs this executable
// there with GIMBALSIM_IN_NETNS=1, which the inner test requires.
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "../lcm_wire/multicast_sender.hpp"
#include "gimbalsim/lcm_wire/udpm_receiver.hpp"
#include "gimbalsim/lcm_wire/udpm_sender.hpp"
#include "hil_util.hpp"

namespace gimbalsim::hil {
namespace {

namespace bio = lcm_wire;

TEST(UdpmInterop, LiblcmMessagesShortAndFragmentedArriveWhole) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("interop");
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  const int rc = runInNetns(dir, "GIMBALSIM_IN_NETNS=1 '" + self + "' --gtest_filter='UdpmInteropInNetns.*'");
  EXPECT_EQ(rc, 0) << readFile(dir / "run.log");
  EXPECT_NE(readFile(dir / "run.log").find("[  PASSED  ] 2 tests"), std::string::npos) << readFile(dir / "run.log");
}

TEST(UdpmInteropInNetns, Liblcm) {
  if (std::getenv("GIMBALSIM_IN_NETNS") == nullptr) GTEST_SKIP() << "runs inside UdpmInterop's network namespace";
  const std::string url = udpmUrl(7791);
  bio::ReassemblyLimits lim;
  lim.max_message_bytes = 256 * 1024;
  lim.max_fragments = 16;
  bio::UdpmReceiver rx(lim, bio::ChannelFilter({"SMALL", "BIG"}));
  std::string why;
  ASSERT_TRUE(rx.open(url, 4 << 20, &why)) << why;
  lcm::LCM lcm(url);
  ASSERT_TRUE(lcm.good());
  std::vector<std::uint8_t> small(100), big(200000);
  for (std::size_t i = 0; i < small.size(); ++i) small[i] = static_cast<std::uint8_t>(i);
  for (std::size_t i = 0; i < big.size(); ++i) big[i] = static_cast<std::uint8_t>(i * 7 + i / 256);
  ASSERT_EQ(lcm.publish("SMALL", small.data(), static_cast<unsigned>(small.size())), 0);
  ASSERT_TRUE(rx.kernelFilter()) << rx.summary();
  for (const char* other : {"OTHER", "SMALLER", "SMAL", "BIGS", "S"}) {
    ASSERT_EQ(lcm.publish(other, small.data(), static_cast<unsigned>(small.size())), 0);
  }
  bio::MulticastSender raw;  // not LCM: no magic
  ASSERT_TRUE(raw.open(bio::parseLcmUrl(url, nullptr)));
  const std::string garbage = "not an LCM datagram";
  ASSERT_TRUE(raw.send(garbage.data(), garbage.size()));
  ASSERT_EQ(lcm.publish("BIG", big.data(), static_cast<unsigned>(big.size())), 0);
  std::vector<std::pair<std::string, std::vector<std::uint8_t>>> got;
  for (int i = 0; i < 50 && got.size() < 2; ++i) {
    if (rx.wait(100) > 0) {
      rx.drain([&](const bio::Message& m, std::int64_t) {
        got.emplace_back(std::string(m.channel), std::vector<std::uint8_t>(m.data, m.data + m.size));
      }, 100);
    }
  }
  ASSERT_EQ(got.size(), 2u) << rx.summary();
  EXPECT_EQ(got[0].first, "SMALL");
  EXPECT_EQ(got[0].second, small);
  EXPECT_EQ(got[1].first, "BIG");
  EXPECT_EQ(got[1].second, big);
  const bio::ReassemblyCounters& c = rx.counters();
  EXPECT_EQ(c.reassembled, 1u);
  // SMALL, the garbage, and BIG's 200000 bytes in fragments of 65487: 4 datagrams.
  for (int i = 0; i < 20 && c.datagrams < 1u + 1u + 4u; ++i) {
    if (rx.wait(50) > 0) rx.drain([](const bio::Message&, std::int64_t) {}, 100);
  }
  EXPECT_EQ(c.datagrams, 1u + 1u + 4u) << rx.summary();
  EXPECT_EQ(c.drops[static_cast<int>(bio::Drop::NotSubscribed)], 0u) << rx.summary();
  EXPECT_EQ(c.drops[static_cast<int>(bio::Drop::BadMagic)], 1u) << rx.summary();
  EXPECT_EQ(c.dropped(), 1u) << rx.summary();

  // Busy-polling (lockstep --spin-us): with nothing sent the spin ends empty;
  // a message sent 5 ms into a spin with no sleeping part (timeout 0) is seen
  // by the spin itself.
  EXPECT_EQ(rx.wait(0, 2000000), 0) << "2 ms spin, nothing sent";
  std::thread late([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    lcm.publish("SMALL", small.data(), static_cast<unsigned>(small.size()));
  });
  const int spun = rx.wait(0, 5000000000LL);  // up to 5 s: ends when the message arrives
  late.join();
  EXPECT_EQ(spun, 1);
}

TEST(UdpmInteropInNetns, OurSender) {
  if (std::getenv("GIMBALSIM_IN_NETNS") == nullptr) GTEST_SKIP() << "runs inside UdpmInterop's network namespace";
  const std::string url = udpmUrl(7792);
  lcm::LCM lcm(url);
  ASSERT_TRUE(lcm.good());
  std::vector<std::pair<std::string, std::vector<std::uint8_t>>> heard;  // by liblcm
  struct Handler {
    std::vector<std::pair<std::string, std::vector<std::uint8_t>>>* out;
    void on(const lcm::ReceiveBuffer* b, const std::string& channel) {
      const auto* p = static_cast<const std::uint8_t*>(b->data);
      out->emplace_back(channel, std::vector<std::uint8_t>(p, p + b->data_size));
    }
  } handler{&heard};
  lcm.subscribe("A", &Handler::on, &handler);
  lcm.subscribe("B", &Handler::on, &handler);
  bio::UdpmReceiver rx({}, bio::ChannelFilter({"A", "B"}));
  std::string why;
  ASSERT_TRUE(rx.open(url, 4 << 20, &why)) << why;
  bio::UdpmSender tx;
  ASSERT_TRUE(tx.open(url, &why)) << why;

  // 11 messages staged: the 9th fills no batch of 8 twice, so one goes out when the batch is full
  // and the rest at flush; payloads differ so order and content are both checked.
  std::vector<std::pair<std::string, std::vector<std::uint8_t>>> sent;
  for (int i = 0; i < 11; ++i) {
    std::vector<std::uint8_t> payload(static_cast<std::size_t>(10 + 37 * i));
    for (std::size_t k = 0; k < payload.size(); ++k) payload[k] = static_cast<std::uint8_t>(k * 13 + i);
    const std::string channel = i % 3 == 1 ? "B" : "A";
    ASSERT_TRUE(tx.stage(channel, [&](void* buf, int cap) {
      if (static_cast<std::size_t>(cap) < payload.size()) return -1;
      std::memcpy(buf, payload.data(), payload.size());
      return static_cast<int>(payload.size());
    }));
    sent.emplace_back(channel, payload);
  }
  EXPECT_EQ(tx.staged(), 3) << "8 went out when the batch filled";
  EXPECT_EQ(tx.flush(), 0);
  EXPECT_EQ(tx.sent(), 11);
  // Refused, counted, nothing sent: a payload beyond a slot, a channel LCM cannot carry.
  EXPECT_FALSE(tx.stage("A", [](void*, int cap) { return cap + 1; }));
  EXPECT_FALSE(tx.stage(std::string(64, 'c'), [](void*, int) { return 1; }));
  EXPECT_FALSE(tx.stage("A", [](void*, int) { return -1; }));
  EXPECT_EQ(tx.staged(), 0);
  EXPECT_EQ(tx.errors(), 3);

  for (int i = 0; i < 50 && heard.size() < sent.size(); ++i) lcm.handleTimeout(100);
  EXPECT_EQ(heard, sent) << "liblcm heard " << heard.size() << " of " << sent.size();

  // Our receiver: the 11 queued datagrams in one drain (two batched reads and a short one).
  std::vector<std::pair<std::string, std::vector<std::uint8_t>>> got;
  ASSERT_EQ(rx.wait(1000), 1);
  const int read = rx.drain([&](const bio::Message& m, std::int64_t) {
    got.emplace_back(std::string(m.channel), std::vector<std::uint8_t>(m.data, m.data + m.size));
  }, 100);
  EXPECT_EQ(read, 11);
  EXPECT_EQ(got, sent) << rx.summary();
  // A drain bounded below what is waiting stops at its bound; the rest waits for the next.
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(tx.stage("A", [](void* buf, int) {
      std::memset(buf, 7, 4);
      return 4;
    }));
  }
  ASSERT_EQ(tx.flush(), 0);
  ASSERT_EQ(rx.wait(1000), 1);
  int n = 0;
  EXPECT_EQ(rx.drain([&n](const bio::Message&, std::int64_t) { ++n; }, 3), 3);
  EXPECT_EQ(n, 3);
  EXPECT_EQ(rx.drain([&n](const bio::Message&, std::int64_t) { ++n; }, 100), 2);
  EXPECT_EQ(n, 5);
}

// A host with no multicast route (a fresh network namespace): joining the group fails, and the reason
// says how to add the route (the programs print it as their exit-5 line).
TEST(UdpmInterop, NoMulticastRouteSaysHowToAddOne) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("noroute");
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  const int rc = runInNetns(dir, "ip route del 224.0.0.0/4 dev lo || exit 96\nGIMBALSIM_IN_NETNS_NO_ROUTE=1 '" + self +
                                     "' --gtest_filter='UdpmNoRouteInNetns.*'");
  EXPECT_EQ(rc, 0) << readFile(dir / "run.log");
  EXPECT_NE(readFile(dir / "run.log").find("[  PASSED  ] 1 test"), std::string::npos) << readFile(dir / "run.log");
}

TEST(UdpmNoRouteInNetns, ReceiverOpen) {
  if (std::getenv("GIMBALSIM_IN_NETNS_NO_ROUTE") == nullptr) GTEST_SKIP() << "runs inside a namespace with no route";
  bio::UdpmReceiver rx(bio::ReassemblyLimits{}, bio::ChannelFilter({"A"}));
  std::string why;
  ASSERT_FALSE(rx.open(udpmUrl(7792), 1 << 20, &why));
  EXPECT_NE(why.find("IP_ADD_MEMBERSHIP: No such device (no multicast route: ip link set lo up && "
                     "ip route add 224.0.0.0/4 dev lo)"), std::string::npos) << why;
  EXPECT_LT(rx.fd(), 0);  // closed on the failed step
}

}  // namespace
}  // namespace gimbalsim::hil
