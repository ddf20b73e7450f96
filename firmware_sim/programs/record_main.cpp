// gimbalsim_record: writes every LCM message of a bench to an LCM log file
// (the lcm-logger format: lcm-logplayer, lcm-spy and gimbalsim_log2csv read
// it). Why not lcm-logger: LCM 1.3.1 queues at most 30 messages per
// subscription (lcm-logger drops the rest when it is off the CPU for ~10 ms,
// seen on a loaded 2-core machine) and its receive thread crashes on one
// malformed fragment. This recorder receives with our bounded receiver
// (lcm_wire/udpm_receiver.hpp: a 16 MB socket buffer unless the URL sets one,
// messages up to kMaxMessageBytes, kMaxPartials in reassembly at once, every
// drop counted) and writes with a checked writer into a temporary file that
// is renamed over FILE when it stops, so FILE is always a whole log.
//
//   gimbalsim_record --lcm-url URL [--channel REGEX] [--duration S] FILE
//
// Stops on SIGINT/SIGTERM (or after --duration wall seconds) and prints how
// many messages it wrote and what the receiver dropped. Exit codes
// (docs/usage.md): 0 ok, 2 bad arguments or output file, 4 writing the log
// failed, 5 cannot receive on the URL, 128 + N stopped by signal N.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <regex>
#include <string>

#include "gimbalsim/io/output_file.hpp"
#include "gimbalsim/lcm_wire/lcm_log.hpp"
#include "gimbalsim/lcm_wire/peak_memory.hpp"
#include "gimbalsim/lcm_wire/udpm_receiver.hpp"
#include "gimbalsim/program/program.hpp"

namespace {

namespace bio = gimbalsim::lcm_wire;
namespace program = gimbalsim::program;
namespace io = gimbalsim::io;

constexpr std::size_t kMaxMessageBytes = 1 << 20;  ///< larger messages are dropped (counted) [bytes]
constexpr int kMaxPartials = 8;                    ///< so at most 8 MiB of reassembly buffers
constexpr int kRecvBufferBytes = 16 << 20;         ///< socket receive buffer asked for: rides out ~0.5 s off the CPU under a flood [bytes]

/// The --channel regex as the receiver's filter: only matching channels are reassembled.
bool matches(void* re, std::string_view channel) {
  return std::regex_match(channel.begin(), channel.end(), *static_cast<const std::regex*>(re));
}

int mainImpl(int argc, char** argv) {
  std::string url, regex = ".*", path;
  double duration = 0.0;
  CLI::App app{"gimbalsim_record: every LCM message of a bench to an LCM log file (lcm-logger format), "
               "without lcm-logger's 30-message queue limit"};
  app.add_option("file", path, "log file to write (replaced when the recording ends)")->required();
  app.add_option("--lcm-url", url, "LCM provider URL, e.g. udpm://239.255.76.67:7667?ttl=0")
      ->check(CLI::Validator(gimbalsim::lcm_wire::lcmUrlProblem, "URL"));
  app.add_option("--channel", regex, "channel regex to record")->capture_default_str();
  app.add_option("--duration", duration, "stop after this many wall seconds (0 = at SIGINT/SIGTERM)")
      ->check(program::within(0.0, 1e9));  // (as int64 ns: no overflow)
  if (const auto rc = program::parse(app, argc, argv, "gimbalsim_record")) return *rc;
  if (const std::string why = gimbalsim::lcm_wire::defaultLcmUrlProblem(url); !why.empty()) {
    return program::refuse("gimbalsim_record", why);
  }
  std::regex re;
  try {
    re = std::regex(regex);
  } catch (const std::regex_error& e) {
    return program::refuse("gimbalsim_record", "--channel '" + regex + "': not a regex (" + e.what() + ")");
  }
  try {  // a path no output may take (a link, a folder, no such folder): refused (exit 2)
    io::checkOutputPaths({path});
  } catch (const io::OutputError& e) {
    return program::refuse("gimbalsim_record", e.what());
  }
  bio::LogWriter log;
  if (std::string why; !log.open(path, &why)) {  // a folder that takes no file: could not be written (4)
    return program::unwritable("gimbalsim_record", why);
  }
  bio::ReassemblyLimits lim;
  lim.max_message_bytes = kMaxMessageBytes;
  lim.max_partials = kMaxPartials;
  lim.max_fragments = 1024;  // 1 MiB in fragments of LCM's smallest payload (1423 bytes, macOS senders)
  bio::UdpmReceiver rx(lim, bio::ChannelFilter(&matches, &re));
  if (std::string why; !rx.open(url, kRecvBufferBytes, &why)) {
    std::fprintf(stderr, "gimbalsim_record: error: cannot receive: %s\n", why.c_str());
    return program::kNetwork;
  }
  io::installStopHandlers();  // without SA_RESTART: the wait returns at once
  std::fprintf(stderr, "gimbalsim_record: recording %s -> %s until SIGINT/SIGTERM%s\n", url.empty() ? "(default URL)" : url.c_str(),
               path.c_str(), duration > 0.0 ? " or --duration" : "");

  long long failed = 0;
  auto write = [&](const bio::Message& m, std::int64_t recv_utime) {
    if (!log.write(recv_utime, m.channel, m.data, m.size)) ++failed;
  };
  const std::int64_t end = bio::monotonicNs() + static_cast<std::int64_t>(duration * 1e9);
  int rc = program::kOk;
  while (!io::stopRequested() && failed == 0 && (duration <= 0.0 || bio::monotonicNs() < end)) {
    if (rx.wait(100) < 0) {
      std::fprintf(stderr, "gimbalsim_record: error: receive failed (socket error)\n");
      rc = program::kNetwork;
      break;
    }
    rx.drain(write, 1024);
  }
  // What the socket holds already is still written (bounded: a flood cannot keep it going).
  if (failed == 0) rx.drain(write, 1 << 16);
  std::string why = failed > 0 ? log.error() : "";
  const bool written = failed == 0 && log.commit(&why);
  if (!written) {
    std::fprintf(stderr, "gimbalsim_record: error: writing %s failed: %s; the file was not replaced\n", path.c_str(),
                 why.c_str());
    rc = program::kOutput;
  }
  std::fprintf(stderr, "gimbalsim_record: %lld messages %s %s; receive: %s; peak memory (VmHWM) %ld kB\n",
               static_cast<long long>(log.events()), written ? "->" : "received, none kept: not written to",
               path.c_str(), rx.summary().c_str(), bio::peakRssKb());
  // Stopped by SIGINT/SIGTERM, the log whole: 128 + the signal.
  return rc == program::kOk && io::stopRequested() ? io::stopExitCode() : rc;
}

}  // namespace

int main(int argc, char** argv) {
  return program::guardedMain("gimbalsim_record", [&] { return mainImpl(argc, argv); });
}
