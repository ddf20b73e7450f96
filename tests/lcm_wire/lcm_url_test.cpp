// parseLcmUrl: the receive side understands the URLs lcm_create does
// (udpm://GROUP:PORT?ttl=N&recv_buf_size=N, memq://, the LCM_DEFAULT_URL
// environment variable, LCM's default) and refuses the rest, saying why.
#include <gtest/gtest.h>
#include <arpa/inet.h>

#include <cstdlib>
#include <string>

#include "gimbalsim/lcm_wire/udpm_receiver.hpp"

namespace gimbalsim::lcm_wire {
namespace {

TEST(LcmUrl, UdpmGroupPortAndOptions) {
  std::string why;
  const LcmUrl u = parseLcmUrl("udpm://239.255.76.67:7734?ttl=0&recv_buf_size=2097152", &why);
  ASSERT_EQ(u.kind, LcmUrl::Kind::Udpm) << why;
  EXPECT_EQ(ntohl(u.group), (239u << 24) | (255u << 16) | (76u << 8) | 67u);
  EXPECT_EQ(u.port, 7734);
  EXPECT_EQ(u.recv_buf_size, 2097152);
  EXPECT_EQ(parseLcmUrl("udpm://239.1.2.3", &why).port, 7667) << "LCM's default port";
  EXPECT_EQ(parseLcmUrl("udpm://", &why).kind, LcmUrl::Kind::Udpm) << "LCM's default group and port: " << why;
  EXPECT_EQ(parseLcmUrl("memq://", &why).kind, LcmUrl::Kind::InProcess);
}

TEST(LcmUrl, EmptyMeansTheEnvironmentThenLcmsDefault) {
  std::string why;
  ::unsetenv("LCM_DEFAULT_URL");
  EXPECT_EQ(parseLcmUrl("", &why).text, "udpm://239.255.76.67:7667?ttl=0");
  ::setenv("LCM_DEFAULT_URL", "udpm://239.9.9.9:7001", 1);
  const LcmUrl u = parseLcmUrl("", &why);
  ::unsetenv("LCM_DEFAULT_URL");
  EXPECT_EQ(u.text, "udpm://239.9.9.9:7001");
  EXPECT_EQ(u.port, 7001);
}

TEST(LcmUrl, RefusalsSayWhy) {
  const std::pair<const char*, const char*> cases[] = {
      {"bogus://x", "provider 'bogus' is not received here"},
      {"udpm-no-separator", "expected provider://network?options"},
      {"udpm://10.0.0.1:7667", "'10.0.0.1' is not a multicast group"},
      {"udpm://239.1.1.1:0", "port '0' is not a whole number in 1..65535"},
      {"udpm://239.1.1.1:99999", "port '99999' is not a whole number in 1..65535"},
      // LCM's publisher reads 07815 as octal (port 7): the receiver taking 7815 would never meet it
      {"udpm://239.1.1.1:07815", "port '07815' is not a whole number in 1..65535 written without a leading zero"},
      {"udpm://239.1.1.1:7667x", "port '7667x'"},
      {"udpm://not.an.ip:7667", "is not an IPv4 address"},
      {"udpm://239.1.1.1:7667?recv_buf_size=-5", "recv_buf_size '-5'"},
      {"udpm://239.1.1.1:7667?bogus=1", "unknown option 'bogus'"},
      // (pass 33) LCM keeps its default ttl when it cannot read one: a mistyped ttl=0 left the host
      {"udpm://239.1.1.1:7667?ttl=abc", "ttl 'abc' is not a whole number in 0..255"},
      {"udpm://239.1.1.1:7667?ttl=", "ttl '' is not a whole number in 0..255"},
      {"udpm://239.1.1.1:7667?ttl=300", "ttl '300'"},
      {"udpm://239.1.1.1:7667?ttl=-1", "ttl '-1'"},
      {"udpm://239.1.1.1:7667?ttl=0&transmit_only=banana", "transmit_only 'banana' is not true or false"},
      {"udpm://:7667?ttl=0", "'' is not an IPv4 address"},
      {"udpm://239.1.1.1:7667?ttl=0&=5", "an option without a name ('=5')"},  // (pass 34)
      // (pass 35) LCM reads the last of two: which one the user meant is not known
      {"udpm://239.1.1.1:7667?ttl=1&ttl=0", "option 'ttl' given twice"},
      {"udpm://239.1.1.1:7667?ttl=0&", "an empty option"},
      {"udpm://239.1.1.1:7667?&&ttl=0", "an empty option"},
      {"udpm://239.1.1.1:7667?", "an empty option"},
  };
  for (const auto& [url, reason] : cases) {
    std::string why;
    EXPECT_EQ(parseLcmUrl(url, &why).kind, LcmUrl::Kind::Unsupported) << url;
    EXPECT_NE(why.find(reason), std::string::npos) << url << ": " << why;
    EXPECT_NE(why.find(url), std::string::npos) << "the message names the URL: " << why;
  }
}

TEST(LcmUrl, TheEnvironmentsUrlIsCheckedAsTheFlagIs) {
  ::setenv("LCM_DEFAULT_URL", "udpm://239.9.9.9:07001", 1);
  const std::string bad = defaultLcmUrlProblem("");
  const std::string given = defaultLcmUrlProblem("udpm://239.9.9.9:7001");
  ::unsetenv("LCM_DEFAULT_URL");
  EXPECT_NE(bad.find("LCM_DEFAULT_URL (the URL without --lcm-url): LCM URL 'udpm://239.9.9.9:07001': port"),
            std::string::npos) << bad;
  EXPECT_EQ(given, "") << "a URL given is the flag's to check";
  EXPECT_EQ(defaultLcmUrlProblem(""), "") << "LCM's own default";
}

}  // namespace
}  // namespace gimbalsim::lcm_wire
