// The validating LCM log reader and the writer (lcm_wire/lcm_log.hpp): a log
// written by liblcm's own writer reads back event for event; ours reads back
// in liblcm's reader; every malformed header is refused with its byte offset.
#include "gimbalsim/lcm_wire/lcm_log.hpp"

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace gimbalsim::lcm_wire {
namespace {

using Bytes = std::vector<std::uint8_t>;

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("gimbalsim_log_" + name + "_" + std::to_string(::getpid())))
      .string();
}

void putBe(Bytes& b, std::uint64_t v, int n) {
  for (int i = n - 1; i >= 0; --i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

/// One event, built from the format's description (not by the code under test).
Bytes event(std::int64_t num, std::int64_t t, const std::string& ch, const Bytes& data, std::uint32_t sync = kLogSync,
            std::int64_t ch_len = -1, std::int64_t data_len = -1) {
  Bytes b;
  putBe(b, sync, 4);
  putBe(b, static_cast<std::uint64_t>(num), 8);
  putBe(b, static_cast<std::uint64_t>(t), 8);
  putBe(b, static_cast<std::uint64_t>(ch_len >= 0 ? ch_len : static_cast<std::int64_t>(ch.size())), 4);
  putBe(b, static_cast<std::uint64_t>(data_len >= 0 ? data_len : static_cast<std::int64_t>(data.size())), 4);
  b.insert(b.end(), ch.begin(), ch.end());
  b.insert(b.end(), data.begin(), data.end());
  return b;
}

std::string readError(const Bytes& log, std::uint64_t* offset = nullptr, int* events = nullptr,
                      std::uint64_t* cut = nullptr) {
  LogReader r;
  r.openMemory(log.data(), log.size());
  LogEvent e;
  int n = 0;
  while (r.next(&e)) ++n;
  if (offset) *offset = r.errorOffset();
  if (events) *events = n;
  if (cut) *cut = r.truncated() ? r.cutBytes() : 0;
  return r.error();
}

TEST(LcmLog, ReadsWhatLiblcmWrote) {
  const std::string path = tempPath("liblcm");
  {
    lcm::LogFile w(path, "w");
    ASSERT_TRUE(w.good());
    for (int i = 0; i < 3; ++i) {
      std::string data(static_cast<std::size_t>(10 * i), static_cast<char>('a' + i));
      lcm::LogEvent e;
      e.timestamp = 1000 + i;
      e.channel = "CH_" + std::to_string(i);
      e.datalen = static_cast<int32_t>(data.size());
      e.data = data.data();
      ASSERT_EQ(w.writeEvent(&e), 0);
    }
  }
  LogReader r;
  std::string why;
  ASSERT_TRUE(r.open(path, &why)) << why;
  LogEvent e;
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(r.next(&e)) << r.error();
    EXPECT_EQ(e.timestamp, 1000 + i);
    EXPECT_EQ(e.eventnum, i);
    EXPECT_EQ(e.channel, "CH_" + std::to_string(i));
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(e.data), e.size), std::string(10 * i, static_cast<char>('a' + i)));
  }
  EXPECT_FALSE(r.next(&e));
  EXPECT_EQ(r.error(), "");
  std::filesystem::remove(path);
}

TEST(LcmLog, LiblcmReadsWhatOurWriterWrote) {
  const std::string path = tempPath("ours");
  {
    LogWriter w;
    std::string why;
    ASSERT_TRUE(w.open(path, &why)) << why;
    const Bytes d{1, 2, 3, 4, 5};
    ASSERT_TRUE(w.write(42, "GIMBAL_TRUTH", d.data(), d.size()));
    ASSERT_TRUE(w.write(43, "X", d.data(), 0));
    ASSERT_TRUE(w.commit(&why)) << why;
  }
  lcm::LogFile r(path, "r");
  ASSERT_TRUE(r.good());
  const lcm::LogEvent* e = r.readNextEvent();
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->timestamp, 42);
  EXPECT_EQ(e->channel, "GIMBAL_TRUTH");
  ASSERT_EQ(e->datalen, 5);
  EXPECT_EQ(static_cast<const std::uint8_t*>(e->data)[4], 5);
  e = r.readNextEvent();
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->eventnum, 1);
  EXPECT_EQ(e->datalen, 0);
  EXPECT_EQ(r.readNextEvent(), nullptr);
  std::filesystem::remove(path);
}

TEST(LcmLog, EmptyFileIsALogWithoutEvents) {
  EXPECT_EQ(readError({}), "");
}

TEST(LcmLog, EveryMalformedHeaderIsRefusedWithItsByteOffset) {
  const Bytes good = event(0, 1, "CH", {1, 2, 3});
  const std::uint64_t second = good.size();
  auto after = [&](const Bytes& bad) {
    Bytes b = good;
    b.insert(b.end(), bad.begin(), bad.end());
    return b;
  };
  struct Case {
    const char* what;
    Bytes log;
    const char* message;
    std::uint64_t cut = 0;  ///< a cut tail (a killed logger): its bytes; 0 = malformed
  };
  const std::vector<Case> cases = {
      {"bad sync word", after(event(1, 2, "CH", {1}, 0xEDA1DA02)), "bad sync word 0xEDA1DA02"},
      {"huge data length", after(event(1, 2, "CH", {1}, kLogSync, -1, 0x7FFFFFFF)), "data length 2147483647 outside"},
      {"negative data length", after(event(1, 2, "CH", {1}, kLogSync, -1, 0xFFFFFFFF)), "data length -1 outside"},
      {"zero channel length", after(event(1, 2, "CH", {1}, kLogSync, 0)), "channel length 0 outside [1, 999]"},
      {"channel length 1000", after(event(1, 2, "CH", {1}, kLogSync, 1000)), "channel length 1000 outside"},
      // A file that ends inside its last event is a cut tail, told apart from a malformed one.
      {"lengths beyond the file", after(event(1, 2, "CH", {1}, kLogSync, -1, 1000)),
       "declares 2 channel + 1000 data bytes, but only 3 bytes follow", 28 + 3},
      {"truncated header", after(Bytes(good.begin(), good.begin() + 27)), "truncated event header (27 of 28 bytes)", 27},
      {"a header cut after garbage", after(Bytes{0x00, 0x01, 0x02}), "truncated event header (3 of 28 bytes)"},
  };
  for (const Case& c : cases) {
    std::uint64_t off = 0, cut = 0;
    int events = 0;
    const std::string err = readError(c.log, &off, &events, &cut);
    EXPECT_EQ(off, second) << c.what;
    EXPECT_EQ(events, 1) << c.what << ": the good event before it was read";
    const std::string kind = c.cut > 0 ? "truncated" : "malformed";
    EXPECT_NE(err.find(kind + " LCM log at byte offset " + std::to_string(second)), std::string::npos) << err;
    EXPECT_NE(err.find(c.message), std::string::npos) << c.what << ": " << err;
    EXPECT_EQ(cut, c.cut) << c.what;
  }
  // At the very start: offset 0.
  std::uint64_t off = 1;
  EXPECT_NE(readError(event(0, 0, "CH", {}, 0x12345678), &off).find("byte offset 0"), std::string::npos);
  EXPECT_EQ(off, 0u);
}

TEST(LcmLog, RefusesAPathThatIsNotARegularFile) {
  LogReader r;
  std::string why;
  EXPECT_FALSE(r.open("/dev/zero", &why));
  EXPECT_NE(why.find("not a regular file"), std::string::npos) << why;
  EXPECT_FALSE(r.open("/nonexistent.lcmlog", &why));
  EXPECT_NE(why.find("No such file"), std::string::npos) << why;
}

// A full disk (here a file-size limit): the writer says the system's reason, naming the file,
// and nothing is left under the name (the recorder prints that reason, not a bare "failed").
TEST(LcmLog, AWriteThatFailsSaysTheSystemsReason) {
  const std::string path = tempPath("full");
  std::filesystem::remove(path);
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {  // the limit is the child's alone
    std::signal(SIGXFSZ, SIG_IGN);
    const rlimit lim{4096, 4096};
    ::setrlimit(RLIMIT_FSIZE, &lim);
    LogWriter w;
    std::string why;
    if (!w.open(path, &why)) _exit(10);
    const std::vector<std::uint8_t> data(1000, 7);
    bool failed = false;
    for (int i = 0; i < 100 && !failed; ++i) failed = !w.write(i, "CH", data.data(), data.size());
    if (!failed && w.commit(&why)) _exit(11);  // the limit must have been met
    const std::string err = failed ? w.error() : why;
    std::fprintf(stderr, "error: %s\n", err.c_str());
    if (err.find(path) == std::string::npos || err.find("File too large") == std::string::npos) _exit(12);
    if (w.commit(&why) || why.find("File too large") == std::string::npos) _exit(13);
    _exit(std::filesystem::exists(path) ? 14 : 0);
  }
  int st = 0;
  ASSERT_EQ(::waitpid(pid, &st, 0), pid);
  ASSERT_TRUE(WIFEXITED(st));
  EXPECT_EQ(WEXITSTATUS(st), 0) << "10 open, 11 no failure, 12 no reason, 13 commit, 14 a file left";
}

}  // namespace
}  // namespace gimbalsim::lcm_wire
