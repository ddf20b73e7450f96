// gimbalsim_record: writes every LCM message of a bench to an LCM log file
// (the lcm-logger format: lcm-logplayer, lcm-spy and gimbalsim_log2csv read
// it). Why not lcm-logger: LCM 1.3.1 queues at most 30 messages per
// subscription and lcm-logger does not raise that, so in lockstep (as fast as
// the pair goes) a logger that is off the CPU for ~10 ms drops messages; seen
// on a loaded 2-core machine. This recorder subscribes with a queue of 1e6
// messages and asks for a 4 MB socket buffer unless the URL sets one.
//
//   gimbalsim_record --lcm-url URL [--channel REGEX] [--duration S] FILE
//
// Stops on SIGINT/SIGTERM (or after --duration wall seconds) and prints how
// many messages it wrote. Exit 0 ok, 2 bad arguments or file, 4 LCM failed.
#include <CLI/CLI.hpp>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <lcm/lcm-cpp.hpp>
#include <string>

namespace {

std::atomic<bool> g_stop{false};
extern "C" void onSignal(int) { g_stop.store(true); }

struct Recorder {
  lcm::LogFile* log = nullptr;
  long long written = 0, failed = 0;
  void onMessage(const lcm::ReceiveBuffer* rb, const std::string& channel) {
    lcm::LogEvent e;
    e.eventnum = 0;  // set by the writer
    e.timestamp = rb->recv_utime;
    e.channel = channel;
    e.datalen = static_cast<int32_t>(rb->data_size);
    e.data = rb->data;
    if (log->writeEvent(&e) == 0) ++written;
    else ++failed;
  }
};

}  // namespace

int main(int argc, char** argv) {
  std::string url, regex = ".*", path;
  double duration = 0.0;
  CLI::App app{"gimbalsim_record: every LCM message of a bench to an LCM log file (lcm-logger format), "
               "without lcm-logger's 30-message queue limit"};
  app.add_option("file", path, "log file to write (overwritten)")->required();
  app.add_option("--lcm-url", url, "LCM provider URL, e.g. udpm://239.255.76.67:7667?ttl=0");
  app.add_option("--channel", regex, "channel regex to record")->capture_default_str();
  app.add_option("--duration", duration, "stop after this many wall seconds (0 = at SIGINT/SIGTERM)")
      ->check(CLI::NonNegativeNumber);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::printf("%s", app.help().c_str());
    return 0;
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "gimbalsim_record: error: %s (see --help)\n", e.what());
    return 2;
  }
  if (url.rfind("udpm://", 0) == 0 && url.find("recv_buf_size") == std::string::npos) {
    url += (url.find('?') == std::string::npos ? "?" : "&") + std::string("recv_buf_size=4194304");
  }
  lcm::LogFile log(path, "w");
  if (!log.good()) {
    std::fprintf(stderr, "gimbalsim_record: error: cannot open '%s' for writing (%s)\n", path.c_str(),
                 std::strerror(errno));
    return 2;
  }
  lcm::LCM lcm(url);
  if (!lcm.good()) {
    std::fprintf(stderr, "gimbalsim_record: error: LCM could not start with URL '%s'\n", url.c_str());
    return 4;
  }
  Recorder r;
  r.log = &log;
  lcm::Subscription* sub = lcm.subscribe(regex, &Recorder::onMessage, &r);
  sub->setQueueCapacity(1000000);
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(duration);
  while (!g_stop.load() && (duration <= 0.0 || std::chrono::steady_clock::now() < end)) {
    if (lcm.handleTimeout(100) < 0 && !g_stop.load()) {
      std::fprintf(stderr, "gimbalsim_record: error: LCM receive failed\n");
      return 4;
    }
  }
  // Whatever LCM has queued already is still written.
  while (lcm.handleTimeout(0) > 0) {
  }
  std::fprintf(stderr, "gimbalsim_record: %lld messages -> %s%s\n", r.written, path.c_str(),
               r.failed ? " (some writes FAILED)" : "");
  return r.failed ? 1 : 0;
}
