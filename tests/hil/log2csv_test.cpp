// gimbalsim_log2csv: an lcm-logger recording of a lockstep bench converts to
// the very truth CSV firmware_sim wrote itself (byte for byte), channel
// prefix included; status and command CSVs come out with the same
// conventions; bad input (missing file, not a log, unknown channel, a prefix
// not in the log) is refused with exit code 2 and a message naming it; bad
// messages in a log are skipped and counted.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <vector>

#include "gimbalsim/gimbal_command_t.hpp"
#include "gimbalsim/gimbal_truth_t.hpp"
#include "hil_util.hpp"

namespace gimbalsim::hil {
namespace {

const std::string kTool = std::string("'") + GIMBALSIM_LOG2CSV + "'";

// The antenna's sensors on the bench: their own channel, one message a tick,
// the tracker's size the truth pointing error of the same tick.
TEST(Log2Csv, TheAntennaSensorsHaveTheirOwnChannelOnTheBench) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("log2csv_antenna");
  const std::string url = udpmUrl(7737), cfg = defaultControllerConfig();
  // The tracker's faults: lock lost over [0.6, 0.7) s, a bias on u from 0.75 s.
  std::ofstream(dir / "faults.yaml") << "faults:\n  - {type: tracker_outage, start: 0.6, end: 0.7}\n"
                                        "  - {type: tracker_bias, start: 0.75, bias: [1.0e-4, 0]}\n";
  const std::string body =
      "'" + std::string(GIMBALSIM_RECORD) + "' --lcm-url '" + url + "' bench.lcmlog 2>record.log &\nR=$!\n" +
      "sleep 0.3\n" + "timeout 60 " + pointingController() + " " + cfg + " --lcm-url '" + url + "'" +
      " --duration 0.8 --idle-exit 5 >ctl.log 2>&1 &\n" + "timeout 60 " + firmwareSim() + " " +
      scenePath("paper_spatial2_tracker") + " --lockstep --duration 0.8 --profile " + cfg +
      " --truth-csv truth.csv --faults faults.yaml --lcm-url '" + url +
      "' --start-timeout 10 >fw.log 2>&1\nrc=$?\nsleep 0.3\n" + "kill -INT $R\nwait\nexit $rc";
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "fw.log");
  int st = 0;
  const std::string out = runCapture(kTool + " '" + (dir / "bench.lcmlog") + "' --channel GIMBAL_ANTENNA --out '" +
                                         (dir / "antenna.csv") + "'",
                                     &st);
  ASSERT_EQ(st, 0) << out;
  const Csv a = Csv::read(dir / "antenna.csv"), tr = Csv::read(dir / "truth.csv");
  ASSERT_EQ(tr.rows.size(), 801u);  // t = 0 .. 0.8 s, the antenna message with each
  ASSERT_GE(a.rows.size(), 801u);
  double largest = 0.0;
  const std::int64_t outage_bit = std::int64_t{1} << 28, bias_bit = std::int64_t{1} << 30;  // kinds 14, 15
  for (size_t k = 0; k < a.rows.size(); ++k) {
    const long long seq = a.integer(k, a.col("seq"));
    ASSERT_TRUE(seq >= 0 && seq <= 800);
    const auto row = static_cast<size_t>(seq);
    // The truth CSV's rows go on with the same tick's antenna message.
    for (const char* c : {"tracker_valid", "tracker_outage", "tracker_u_rad", "tracker_v_rad", "antenna_gyro_wy_rad_per_s"}) {
      EXPECT_EQ(tr.rows[row][tr.col(c)], a.rows[k][a.col(c)]) << c << ", tick " << seq;
    }
    const std::int64_t injected = tr.integer(row, tr.col("injected_faults"));
    const bool out_of_lock = seq >= 600 && seq < 700, biased = seq >= 750;
    EXPECT_EQ((injected & outage_bit) != 0, out_of_lock) << "tick " << seq;
    EXPECT_EQ((injected & bias_bit) != 0, biased) << "tick " << seq;
    EXPECT_EQ(a.integer(k, a.col("tracker_outage")), out_of_lock ? 1 : 0) << "tick " << seq;
    // 1 kHz, no latency: each tick's own reading, none while out of lock
    EXPECT_EQ(a.integer(k, a.col("tracker_valid")), out_of_lock ? 0 : 1) << "tick " << seq;
    if (out_of_lock) continue;
    const double e = tr.num(row, tr.col("pointing_error_rad"));
    const double u = a.num(k, a.col("tracker_u_rad")) - (biased ? 1e-4 : 0.0);
    EXPECT_NEAR(std::hypot(u, a.num(k, a.col("tracker_v_rad"))), e, 1e-12 + 1e-9 * e) << "tick " << seq;
    largest = std::max(largest, e);
  }
  EXPECT_GT(largest, 1e-4);  // the slew from 0.5 s turns the antenna: a reading worth checking
}

TEST(Log2Csv, LoggedLockstepRunConvertsToTheTruthCsvFirmwareSimWrote) {
  GIMBALSIM_HIL_REQUIRE_NETNS();
  TempDir dir("log2csv");
  const std::string url = udpmUrl(7735), cfg = defaultControllerConfig(), pfx = " --channel-prefix HIL_L_";
  const bool have_logger = std::system("command -v lcm-logger >/dev/null 2>&1") == 0;
  // Recorders first (gimbalsim_record, and lcm-logger when installed); the
  // run; then SIGINT the recorders (both close their log cleanly).
  const std::string body =
      "'" + std::string(GIMBALSIM_RECORD) + "' --lcm-url '" + url + "' bench.lcmlog 2>record.log &\nR=$!\n" +
      (have_logger ? "lcm-logger --lcm-url='" + url + "' -f -q logger.lcmlog >logger.log 2>&1 &\nL=$!\n"
                   : std::string("L=\n")) +
      "sleep 0.3\n" + "timeout 60 " + pointingController() + " " + cfg + " --lcm-url '" + url + "'" + pfx +
      " --duration 1 --idle-exit 5 >ctl.log 2>&1 &\n" + "timeout 60 " + firmwareSim() + " " +
      scenePath("paper_clearance") + " --lockstep --duration 1 --profile " + cfg + " --truth-csv truth.csv --lcm-url '" +
      url + "'" + pfx + " --start-timeout 10 >fw.log 2>&1\nrc=$?\nsleep 0.3\nkill -INT $R $L\nwait\nexit $rc";
  ASSERT_EQ(runInNetns(dir, body), 0) << readFile(dir / "run.log") << readFile(dir / "fw.log");

  int st = 0;
  std::filesystem::create_directories(dir / "csv");
  const std::string out = runCapture(kTool + " '" + (dir / "bench.lcmlog") + "' --out-dir '" + (dir / "csv") + "'", &st);
  ASSERT_EQ(st, 0) << out;
  EXPECT_NE(out.find("HIL_L_GIMBAL_TRUTH (truth): 1001 rows"), std::string::npos) << out;
  const std::string truth = readFile(dir / "truth.csv");
  ASSERT_GT(truth.size(), 1000u);
  EXPECT_TRUE(readFile(dir / "csv/bench_HIL_L_GIMBAL_TRUTH.csv") == truth)
      << "the truth CSV converted from the log differs from firmware_sim --truth-csv";

  // lcm-logger's log converts the same way; LCM 1.3.1's lcm-logger may drop
  // messages in lockstep on a loaded machine (30-message queue, see
  // record_main.cpp), so: every row it has is the firmware's row, byte for byte.
  if (have_logger) {
    const std::string lout = runCapture(kTool + " '" + (dir / "logger.lcmlog") + "' --channel HIL_L_GIMBAL_TRUTH --out '" +
                                            (dir / "logger_truth.csv") + "'",
                                        &st);
    ASSERT_EQ(st, 0) << lout;
    const Csv fw = Csv::read(dir / "truth.csv"), lg = Csv::read(dir / "logger_truth.csv");
    ASSERT_EQ(lg.header, fw.header);
    ASSERT_GT(lg.rows.size(), 0u);
    const int c_seq = fw.col("seq");
    for (size_t k = 0; k < lg.rows.size(); ++k) {
      const long long seq = lg.integer(k, c_seq);
      ASSERT_TRUE(seq >= 0 && seq < static_cast<long long>(fw.rows.size()));
      EXPECT_EQ(lg.rows[k], fw.rows[static_cast<size_t>(seq)]) << "lcm-logger row of tick " << seq;
    }
    std::printf("lcm-logger kept %zu of %zu truth messages\n", lg.rows.size(), fw.rows.size());
  }

  // Status: one row per status published (status 0 may repeat while waiting
  // for the controller), quantized angles, no faults; commands answer them.
  const Csv s = Csv::read(dir / "csv/bench_HIL_L_GIMBAL_STATUS.csv");
  ASSERT_GE(s.rows.size(), 1000u);
  EXPECT_EQ(s.header.front(), "utime_us");
  EXPECT_EQ(s.integer(s.rows.size() - 1, s.col("seq")), 999);
  for (size_t k = 0; k < s.rows.size(); ++k) EXPECT_EQ(s.integer(k, s.col("faults")), 0);
  const Csv c = Csv::read(dir / "csv/bench_HIL_L_GIMBAL_COMMAND.csv");
  ASSERT_GE(c.rows.size(), 999u);
  EXPECT_EQ(c.integer(c.rows.size() - 1, c.col("status_seq")), 999);
  // Every answer but the last one had arrived by status 999 (status 0 may have been answered twice).
  EXPECT_GE(s.integer(s.rows.size() - 1, s.col("commands_received")), 999);
  EXPECT_LE(s.integer(s.rows.size() - 1, s.col("commands_received")), 1000);

  // Attitude (default: perfect sensors): published with every status; the
  // gyro reads the true base rate, the 10 Hz star tracker delivers the true
  // quaternion at ticks 0, 100, ..., stamped with their own time.
  const Csv a = Csv::read(dir / "csv/bench_HIL_L_GIMBAL_ATTITUDE.csv");
  const Csv tr = Csv::read(dir / "truth.csv");
  ASSERT_GE(a.rows.size(), 1000u);
  ASSERT_EQ(tr.rows.size(), 1001u);  // t = 0 .. 1 s: the last with no status nor attitude
  const char* gyro[] = {"gyro_wx_rad_per_s", "gyro_wy_rad_per_s", "gyro_wz_rad_per_s"};
  const char* base_w[] = {"base_wx_rad_per_s", "base_wy_rad_per_s", "base_wz_rad_per_s"};
  const char* star_q[] = {"star_qw", "star_qx", "star_qy", "star_qz"};
  const char* base_q[] = {"base_qw", "base_qx", "base_qy", "base_qz"};
  int delivered = 0;
  for (size_t k = 0; k < a.rows.size(); ++k) {
    const long long seq = a.integer(k, a.col("seq"));
    ASSERT_TRUE(seq >= 0 && seq < 1000);
    const auto& t = tr.rows[static_cast<size_t>(seq)];
    for (int i = 0; i < 3; ++i) EXPECT_EQ(a.rows[k][a.col(gyro[i])], t[tr.col(base_w[i])]) << "tick " << seq;
    const bool valid = a.integer(k, a.col("star_valid")) == 1;
    EXPECT_EQ(valid, seq % 100 == 0) << "tick " << seq;
    EXPECT_EQ(a.integer(k, a.col("star_outage")), 0);
    if (!valid) continue;
    ++delivered;
    EXPECT_DOUBLE_EQ(a.num(k, a.col("star_time_s")), 1e-3 * static_cast<double>(seq));
    for (int i = 0; i < 4; ++i) EXPECT_EQ(a.rows[k][a.col(star_q[i])], t[tr.col(base_q[i])]) << "tick " << seq;
  }
  EXPECT_GE(delivered, 10);

  // A scene without antenna sensors publishes no GIMBAL_ANTENNA (sensors.antenna none: no cost, no channel).
  EXPECT_EQ(out.find("GIMBAL_ANTENNA"), std::string::npos) << out;

  // One channel to a chosen file, with the logger's receive time in front.
  const std::string one = dir / "one.csv";
  const std::string one_out = runCapture(kTool + " '" + (dir / "bench.lcmlog") +
                                             "' --channel-prefix HIL_L_ --channel HIL_L_GIMBAL_TRUTH --log-time --out '" +
                                             one + "'",
                                         &st);
  ASSERT_EQ(st, 0) << one_out;
  const Csv o = Csv::read(one);
  ASSERT_EQ(o.rows.size(), 1001u);
  EXPECT_EQ(o.header.front(), "log_utime_us");
  EXPECT_EQ(o.header[1], "utime_us");

  // A prefix that is not in the log, and a channel that is not: exit 2, named.
  std::string msg = runCapture(kTool + " '" + (dir / "bench.lcmlog") + "' --channel-prefix BENCH9_", &st);
  EXPECT_EQ(WEXITSTATUS(st), 2);
  EXPECT_NE(msg.find("no channel with --channel-prefix 'BENCH9_' in the log (channels: HIL_L_GIMBAL_ATTITUDE, HIL_L_GIMBAL_COMMAND"),
            std::string::npos)
      << msg;
  msg = runCapture(kTool + " '" + (dir / "bench.lcmlog") + "' --channel GIMBAL_TRUTH", &st);
  EXPECT_EQ(WEXITSTATUS(st), 2);
  EXPECT_NE(msg.find("--channel 'GIMBAL_TRUTH': not in the log"), std::string::npos) << msg;
}

TEST(Log2Csv, RefusesMissingFileAndNonLogWithExitCode2) {
  int st = 0;
  std::string msg = runCapture(kTool + " /nonexistent/run.lcmlog", &st);
  EXPECT_EQ(WEXITSTATUS(st), 2);
  EXPECT_NE(msg.find("log '/nonexistent/run.lcmlog': no such file"), std::string::npos) << msg;
  const std::string yaml = scenePath("paper_clearance");
  msg = runCapture(kTool + " '" + yaml + "'", &st);
  EXPECT_EQ(WEXITSTATUS(st), 2);
  EXPECT_NE(msg.find("not an LCM log"), std::string::npos) << msg;
  msg = runCapture(kTool + " '" + yaml + "' --type bogus --channel X", &st);
  EXPECT_EQ(WEXITSTATUS(st), 2);
  EXPECT_NE(msg.find("--type 'bogus'"), std::string::npos) << msg;
}

/// One event (channel, bytes, timestamp [us]) written to an LCM log file.
void writeEvent(lcm::LogFile& log, const std::string& channel, const void* data, int n, int64_t t) {
  lcm::LogEvent e;
  e.timestamp = t;
  e.channel = channel;
  e.datalen = n;
  e.data = const_cast<void*>(data);
  ASSERT_EQ(log.writeEvent(&e), 0);
}

/// One message encoded and written as an event (channel, timestamp [us]).
template <class Message>
void writeMessage(lcm::LogFile& log, const std::string& channel, const Message& m, int64_t t) {
  std::vector<unsigned char> buf(static_cast<std::size_t>(m.getEncodedSize()));
  writeEvent(log, channel, buf.data(), m.encode(buf.data(), 0, static_cast<int>(buf.size())), t);
}

TEST(Log2Csv, SkipsAndCountsUndecodableMessagesOnAChannel) {
  TempDir dir("log2csv_garbage");
  const std::string path = dir / "w.lcmlog";
  {
    lcm::LogFile log(path, "w");
    ASSERT_TRUE(log.good());
    gimbal_command_t c{};
    c.seq = 3;
    c.status_seq = 2;
    c.mode = gimbal_command_t::MODE_TORQUE;
    c.torque[0] = 0.1;
    c.torque[1] = -1.0 / 3.0;
    writeMessage(log, "GIMBAL_COMMAND", c, 10);
    const char junk[] = "not a command";
    writeEvent(log, "GIMBAL_COMMAND", junk, sizeof junk, 11);
    writeMessage(log, "GIMBAL_COMMAND", gimbal_truth_t{}, 12);  // a wrong type on the command channel
    writeEvent(log, "OTHER_STUFF", junk, sizeof junk, 13);
  }
  int st = 0;
  std::filesystem::create_directories(dir / "o");
  const std::string out = runCapture(kTool + " '" + path + "' --out-dir '" + (dir / "o") + "'", &st);
  ASSERT_EQ(st, 0) << out;
  EXPECT_NE(out.find("GIMBAL_COMMAND (command): 1 rows"), std::string::npos) << out;
  EXPECT_NE(out.find("2 message(s) on GIMBAL_COMMAND are not a command"), std::string::npos) << out;
  EXPECT_EQ(readFile(dir / "o/w_GIMBAL_COMMAND.csv"),
            "utime_us,seq,status_seq,mode,tau1_Nm,tau2_Nm\n0,3,2,1,0.1,"
            "-0.3333333333333333\n");  // the shortest round trip
}

// A channel none of whose messages decodes as its type gave a CSV of a header only, exit 0 (read as "the
// bench sent nothing"): named by --channel it is refused and nothing is written; found by its name it gets
// no CSV, and the console says why.
TEST(Log2Csv, AChannelWithNoDecodableMessageGivesNoEmptyCsv) {
  TempDir dir("log2csv_no_rows");
  const std::string path = dir / "w.lcmlog";
  {
    lcm::LogFile log(path, "w");
    ASSERT_TRUE(log.good());
    gimbal_command_t c{};
    c.mode = gimbal_command_t::MODE_TORQUE;
    writeMessage(log, "GIMBAL_COMMAND", c, 10);
    const char junk[] = "not a status";
    writeEvent(log, "GIMBAL_STATUS", junk, sizeof junk, 11);
  }
  const std::string out = dir / "as_truth.csv";
  std::ofstream(out) << "old\n";
  int st = 0;
  std::string msg =
      runCapture(kTool + " '" + path + "' --channel GIMBAL_COMMAND --type truth --out '" + out + "'", &st);
  EXPECT_EQ(WEXITSTATUS(st), 2) << msg;
  EXPECT_NE(msg.find("--channel 'GIMBAL_COMMAND': none of its 1 message(s) is a whole, finite truth"),
            std::string::npos) << msg;
  EXPECT_NE(msg.find("is --type right?"), std::string::npos) << msg;
  EXPECT_EQ(readFile(out), "old\n");

  std::filesystem::create_directories(dir / "o");
  msg = runCapture(kTool + " '" + path + "' --out-dir '" + (dir / "o") + "'", &st);
  EXPECT_EQ(WEXITSTATUS(st), 0) << msg;
  EXPECT_NE(msg.find("GIMBAL_COMMAND (command): 1 rows"), std::string::npos) << msg;
  EXPECT_NE(msg.find("GIMBAL_STATUS: none of its 1 message(s) is a whole, finite status (1 not one, 0 with a NaN or "
                     "Inf); no CSV written for it"), std::string::npos) << msg;
  EXPECT_TRUE(std::filesystem::exists(dir / "o/w_GIMBAL_COMMAND.csv"));
  EXPECT_FALSE(std::filesystem::exists(dir / "o/w_GIMBAL_STATUS.csv"));
}

// A channel name comes from the log: "/../../x" would have named a CSV outside the output folder.
TEST(Log2Csv, AChannelNameThatCannotNameAFileIsRefused) {
  TempDir dir("log2csv_channel_path");
  const std::string path = dir / "rec.lcmlog";
  {
    lcm::LogFile log(path, "w");
    ASSERT_TRUE(log.good());
    writeMessage(log, "/../../escape_GIMBAL_TRUTH", gimbal_truth_t{}, 1);
  }
  std::filesystem::create_directories(dir / "rec_");  // so that rec_/../../escape... resolves
  int st = 0;
  const std::string out =
      runCapture(kTool + " '" + path + "' --channel '/../../escape_GIMBAL_TRUTH' --type truth 2>&1", &st);
  EXPECT_EQ(WEXITSTATUS(st), 2) << out;
  EXPECT_NE(out.find("only A-Z, 0-9 and '_' can name its CSV file; give --out FILE"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir.path.parent_path() / "escape_GIMBAL_TRUTH.csv"));
  const std::string named = runCapture(kTool + " '" + path + "' --channel '/../../escape_GIMBAL_TRUTH' --type truth " +
                                           "--out '" + (dir / "t.csv") + "' 2>&1",
                                       &st);
  EXPECT_EQ(WEXITSTATUS(st), 0) << named;  // with a file named by the user it converts
}

// (pass 111) a channel name is anyone's bytes on the bus, which gimbalsim_record keeps: --list and the refusal
// naming the log's channels printed U+202E and an escape sequence raw to the terminal
TEST(Log2Csv, ALogsChannelNamesAreShownNeverPrintedRaw) {
  TempDir dir("log2csv_channel_shown");
  const std::string path = dir / "rec.lcmlog";
  {
    lcm::LogFile log(path, "w");
    ASSERT_TRUE(log.good());
    writeMessage(log, "EVIL\u202e\x1b[2J", gimbal_truth_t{}, 1);
    writeMessage(log, std::string("RAW\x9b\tX\xc0\x8a"), gimbal_truth_t{}, 2);  // (pass 113) not UTF-8, a tab
  }
  int st = 0;
  for (const std::string& args : {std::string(" --list"), std::string("")}) {
    const std::string out = runCapture(kTool + " '" + path + "'" + args + " 2>&1", &st);
    EXPECT_EQ(WEXITSTATUS(st), args.empty() ? 2 : 0) << out;
    EXPECT_NE(out.find("EVIL<U+202E><U+001B>[2J"), std::string::npos) << out;
    EXPECT_NE(out.find("RAW<0x9B><U+0009>X<0xC0><0x8A>"), std::string::npos) << out;
    EXPECT_EQ(out.find('\x9b'), std::string::npos) << out;
    EXPECT_EQ(out.find("\x1b"), std::string::npos) << out;
    EXPECT_EQ(out.find("\u202e"), std::string::npos) << out;
  }
}

}  // namespace
}  // namespace gimbalsim::hil

namespace gimbalsim::hil {
namespace {

/// A log with one gimbal_command_t event, by liblcm's writer; its size in bytes (0: failed).
long writeOneCommandLog(const std::string& path) {
  lcm::LogFile log(path, "w");
  if (!log.good()) return 0;
  unsigned char buf[256];
  gimbal_command_t c{};
  const int n = c.encode(buf, 0, sizeof buf);
  lcm::LogEvent e;
  e.timestamp = 1;
  e.channel = "GIMBAL_COMMAND";
  e.datalen = n;
  e.data = buf;
  return log.writeEvent(&e) == 0 ? 28 + static_cast<long>(e.channel.size()) + n : 0;
}

// A log whose second event header declares 2 GB of data (LCM 1.3.1's reader
// trusts it and crashes): refused with exit 2, the byte offset of that event,
// and no CSV written; the log itself is never an output.
TEST(Log2Csv, RefusesAMalformedLogWithTheByteOffsetAndWritesNothing) {
  TempDir dir("log2csv_malformed");
  const std::string path = dir / "m.lcmlog";
  const long first_event_bytes = writeOneCommandLog(path);
  ASSERT_GT(first_event_bytes, 0);
  {
    std::FILE* f = std::fopen(path.c_str(), "ab");
    const unsigned char hdr[28] = {0xED, 0xA1, 0xDA, 0x01, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0,
                                   0,    0,    0,    2,    0, 0, 0, 14, 0x7F, 0xFF, 0xFF, 0xFF};
    std::fwrite(hdr, 1, sizeof hdr, f);
    std::fputs("GIMBAL_COMMAND", f);
    std::fclose(f);
  }
  int st = 0;
  std::string msg = runCapture(kTool + " '" + path + "' --out-dir '" + (dir / "o") + "'", &st);
  EXPECT_EQ(WEXITSTATUS(st), 2) << msg;
  EXPECT_NE(msg.find("malformed LCM log at byte offset " + std::to_string(first_event_bytes)), std::string::npos)
      << msg;
  EXPECT_NE(msg.find("data length 2147483647"), std::string::npos) << msg;
  EXPECT_FALSE(std::filesystem::exists(dir / "o/m_GIMBAL_COMMAND.csv"));
  msg = runCapture(kTool + " '" + path + "' --channel GIMBAL_COMMAND --out '" + path + "'", &st);
  EXPECT_EQ(WEXITSTATUS(st), 2) << msg;
}

TEST(Log2Csv, NeverWritesOverTheLogOrThroughASymlink) {
  TempDir dir("log2csv_outputs");
  const std::string path = dir / "w.lcmlog";
  ASSERT_GT(writeOneCommandLog(path), 0);
  const std::string before = readFile(path);
  int st = 0;
  std::string msg = runCapture(kTool + " '" + path + "' --channel GIMBAL_COMMAND --out '" + path + "'", &st);
  EXPECT_EQ(WEXITSTATUS(st), 2) << msg;
  EXPECT_NE(msg.find("the same file as the input"), std::string::npos) << msg;
  std::filesystem::create_symlink(dir / "elsewhere.txt", dir / "link.csv");
  msg = runCapture(kTool + " '" + path + "' --channel GIMBAL_COMMAND --out '" + (dir / "link.csv") + "'", &st);
  EXPECT_EQ(WEXITSTATUS(st), 2) << msg;
  EXPECT_NE(msg.find("symbolic link"), std::string::npos) << msg;
  EXPECT_FALSE(std::filesystem::exists(dir / "elsewhere.txt"));
  EXPECT_EQ(readFile(path), before);
}


// A log cut inside its last event (a killed logger leaves one; lcm-logplayer
// plays the rest): every whole event is converted, the cut is reported in
// bytes, and the exit code says the input was partial (7).
TEST(Log2Csv, SalvagesEveryWholeEventOfATruncatedLogAndSaysHowMuchWasCut) {
  TempDir dir("log2csv_truncated");
  const std::string path = dir / "t.lcmlog";
  long event_bytes = 0;
  {
    lcm::LogFile log(path, "w");
    ASSERT_TRUE(log.good());
    unsigned char buf[256];
    for (int i = 0; i < 3; ++i) {
      gimbal_command_t c{};
      c.seq = i;
      const int n = c.encode(buf, 0, sizeof buf);
      lcm::LogEvent e;
      e.timestamp = i;
      e.channel = "GIMBAL_COMMAND";
      e.datalen = n;
      e.data = buf;
      ASSERT_EQ(log.writeEvent(&e), 0);
      event_bytes = 28 + static_cast<long>(e.channel.size()) + n;
    }
  }
  std::filesystem::resize_file(path, static_cast<std::uintmax_t>(3 * event_bytes - 10));  // the third event cut
  std::filesystem::create_directories(dir / "o");
  int st = 0;
  std::string msg = runCapture(kTool + " '" + path + "' --out-dir '" + (dir / "o") + "'", &st);
  EXPECT_EQ(WEXITSTATUS(st), 7) << msg;
  EXPECT_NE(msg.find("the last " + std::to_string(event_bytes - 10) + " bytes, from byte offset " +
                     std::to_string(2 * event_bytes) + ", are dropped; the 2 whole events before them are converted"),
            std::string::npos)
      << msg;
  EXPECT_EQ(test::Csv::read(dir / "o/t_GIMBAL_COMMAND.csv").rows.size(), 2u);
  // Cut inside a header: the sync word's first bytes only.
  std::filesystem::resize_file(path, static_cast<std::uintmax_t>(2 * event_bytes + 3));
  msg = runCapture(kTool + " '" + path + "' --channel GIMBAL_COMMAND --out '" + (dir / "h.csv") + "'", &st);
  EXPECT_EQ(WEXITSTATUS(st), 7) << msg;
  EXPECT_NE(msg.find("the last 3 bytes"), std::string::npos) << msg;
  EXPECT_EQ(test::Csv::read(dir / "h.csv").rows.size(), 2u);
  // Cut inside the first event: nothing to salvage, a refusal (exit 2), not a partial result.
  std::filesystem::resize_file(path, 10);
  msg = runCapture(kTool + " '" + path + "' --out-dir '" + (dir / "o") + "'", &st);
  EXPECT_EQ(WEXITSTATUS(st), 2) << msg;
  EXPECT_NE(msg.find("cut inside its first event (10 bytes): no whole event to convert"), std::string::npos) << msg;
  EXPECT_EQ(msg.find("exit 7"), std::string::npos) << msg;
}

// An output folder is never created: a missing one is refused, named (the rule of every program).
TEST(Log2Csv, RefusesAMissingOutputFolderNamingIt) {
  TempDir dir("log2csv_missing_dir");
  const std::string path = dir / "w.lcmlog";
  ASSERT_GT(writeOneCommandLog(path), 0);
  int st = 0;
  const std::string msg = runCapture(kTool + " '" + path + "' --out-dir '" + (dir / "missing/dir") + "'", &st);
  EXPECT_EQ(WEXITSTATUS(st), 2) << msg;
  EXPECT_NE(msg.find("--out-dir '" + (dir / "missing/dir") + "': no such folder"), std::string::npos) << msg;
  EXPECT_FALSE(std::filesystem::exists(dir / "missing"));
  // nor written through a link (pass 66: the CSVs went wherever it pointed)
  std::filesystem::create_directory(dir / "real");
  std::filesystem::create_directory_symlink(dir / "real", dir / "link");
  const std::string linked = runCapture(kTool + " '" + path + "' --out-dir '" + (dir / "link") + "'", &st);
  EXPECT_EQ(WEXITSTATUS(st), 2) << linked;
  EXPECT_NE(linked.find("--out-dir '" + (dir / "link") + "': is a link (to " + (dir / "real") + ")"), std::string::npos)
      << linked;
  EXPECT_TRUE(std::filesystem::is_empty(dir / "real"));
}

// A decoded message carrying a NaN or Inf is no row: a CSV cell holds no Inf, and a NaN needs its reason
// (pass 63: crafted commands on the wire became rows "nan", "inf", "-inf"). Skipped, counted, said.
TEST(Log2Csv, AMessageWithANonFiniteNumberIsSkippedAndCounted) {
  TempDir dir("log2csv_non_finite");
  const std::string path = dir / "w.lcmlog";
  {
    lcm::LogFile log(path, "w");
    ASSERT_TRUE(log.good());
    gimbal_command_t c{};
    c.seq = 1;
    c.mode = gimbal_command_t::MODE_TORQUE;
    for (const double tau : {0.5, std::nan(""), std::numeric_limits<double>::infinity(), -0.25}) {
      c.torque[1] = tau;
      writeMessage(log, "GIMBAL_COMMAND", c, 10);
      ++c.seq;
    }
  }
  std::filesystem::create_directories(dir / "o");
  int st = 0;
  const std::string out = runCapture(kTool + " '" + path + "' --out-dir '" + (dir / "o") + "'", &st);
  ASSERT_EQ(st, 0) << out;
  EXPECT_NE(out.find("GIMBAL_COMMAND (command): 2 rows"), std::string::npos) << out;
  EXPECT_NE(out.find("2 message(s) on GIMBAL_COMMAND carry a NaN or Inf"), std::string::npos) << out;
  EXPECT_EQ(readFile(dir / "o/w_GIMBAL_COMMAND.csv"),
            "utime_us,seq,status_seq,mode,tau1_Nm,tau2_Nm\n0,1,0,1,0,0.5\n0,4,0,1,0,-0.25\n");
}

// The channels' CSVs commit together: on a full disk, exit 4 and no CSV under any name (the small one was
// left while the large one was lost, and all were announced as written). The disk is a 64 KiB tmpfs in a
// private mount namespace.
TEST(Log2Csv, AFullDiskLeavesNoCsvOfTheRun) {
  if (std::system("unshare -m true 2>/dev/null") != 0) GTEST_SKIP() << "no private mount namespace here";
  TempDir dir("log2csv_full_disk");
  const std::string path = dir / "w.lcmlog";
  {
    lcm::LogFile log(path, "w");
    ASSERT_TRUE(log.good());
    std::vector<unsigned char> buf(65536);
    gimbal_command_t c{};
    int n = c.encode(buf.data(), 0, static_cast<int>(buf.size()));
    writeEvent(log, "GIMBAL_COMMAND", buf.data(), n, 1);  // one row: its CSV fits
    gimbal_truth_t t{};
    n = t.encode(buf.data(), 0, static_cast<int>(buf.size()));
    for (int k = 0; k < 2000; ++k) writeEvent(log, "GIMBAL_TRUTH", buf.data(), n, 2 + k);  // far more than 64 KiB
  }
  std::filesystem::create_directories(dir / "o");
  int st = 0;
  const std::string out = runCapture("unshare -m sh -c \"mount -t tmpfs -o size=64k tmpfs '" + (dir / "o") +
                                         "' && " + kTool + " '" + path + "' --out-dir '" + (dir / "o") +
                                         "'; rc=\\$?; ls -A '" + (dir / "o") + "'; exit \\$rc\"",
                                     &st);
  EXPECT_EQ(WEXITSTATUS(st), 4) << out;
  EXPECT_NE(out.find("no CSV written"), std::string::npos) << out;
  EXPECT_EQ(out.find(".csv\n"), std::string::npos) << "a CSV left on the full disk:\n" << out;
  EXPECT_EQ(out.find("rows ->"), std::string::npos) << out;
}

}  // namespace
}  // namespace gimbalsim::hil
