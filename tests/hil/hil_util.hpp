// Helpers of the hardware-in-the-loop tests: the real firmware_sim and
// pointing_controller processes over LCM udpm (ttl=0) on loopback, each test
// in its own network namespace, so runs never leave the host and never meet
// another run (also under ctest -j). Shell scripts drive the processes (start,
// kill -9, restart), as a bench engineer would in two terminals.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "../csv_util.hpp"
#include "../test_util.hpp"

namespace gimbalsim::hil {

/// How to get a private network namespace here: `unshare -n` (root), else
/// `unshare -rn` (a user namespace mapping us to root in it: works
/// unprivileged where user namespaces are enabled). `prefix` empty: neither
/// works, `why_not` says what each attempt answered. GIMBALSIM_HIL_UNSHARE
/// (e.g. "unshare -rn") tries only that command.
struct Netns {
  std::string prefix;
  std::string why_not;
};

inline std::string runCapture(const std::string& cmd, int* status) {
  std::string out;
  if (std::FILE* p = ::popen((cmd + " 2>&1").c_str(), "r")) {
    char buf[512];
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    *status = ::pclose(p);
  } else {
    *status = -1;
  }
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

inline const Netns& netns() {
  static const Netns n = [] {
    Netns r;
    std::vector<std::string> tries = {"unshare -n", "unshare -rn"};
    if (const char* force = std::getenv("GIMBALSIM_HIL_UNSHARE")) tries = {force};  // e.g. "unshare -rn"
    for (const std::string& p : tries) {
      int st = 0;
      const std::string out =
          runCapture(p + " sh -c 'ip link set lo up && ip route add 224.0.0.0/4 dev lo'", &st);
      if (st == 0) {
        r.prefix = p;
        return r;
      }
      r.why_not += std::string(r.why_not.empty() ? "" : "; ") + "`" + p + "`: " + (out.empty() ? "refused" : out);
    }
    return r;
  }();
  return n;
}

#define GIMBALSIM_HIL_REQUIRE_NETNS()                                                                    \
  do {                                                                                                   \
    if (::gimbalsim::hil::netns().prefix.empty()) {                                                      \
      GTEST_SKIP() << "no private network namespace: " << ::gimbalsim::hil::netns().why_not;             \
    }                                                                                                    \
  } while (0)

/// A fresh directory per test (removed when the test passes).
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& name) {
    path = std::filesystem::temp_directory_path() / ("gimbalsim_hil_" + name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    if (!::testing::Test::HasFailure()) std::filesystem::remove_all(path);
  }
  std::string operator/(const std::string& f) const { return (path / f).string(); }
};

/// udpm on loopback that cannot leave the host; one port per test.
inline std::string udpmUrl(int port) { return "udpm://239.255.76.67:" + std::to_string(port) + "?ttl=0"; }

/// Runs `body` with sh inside a fresh network namespace (lo up, multicast
/// route on lo), cwd = dir, output to dir/run.log. Returns the script's exit
/// code (97: the namespace set-up failed; -1: it did not exit normally).
inline int runInNetns(const TempDir& dir, const std::string& body) {
  const std::string script = dir / "run.sh";
  {
    std::ofstream f(script);
    f << "ip link set lo up && ip route add 224.0.0.0/4 dev lo || exit 97\n"
      << "cd '" << dir.path.string() << "' || exit 98\n"
      << body << "\n";
  }
  const std::string cmd = netns().prefix + " sh '" + script + "' >'" + (dir / "run.log") + "' 2>&1";
  const int st = std::system(cmd.c_str());
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

inline std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

using test::Csv;
using test::defaultControllerConfig;
using test::scenePath;

/// firmware_sim's exit summary: "commands: received N, rejected N, missed N;
/// watchdog trips N; ..." and the other counters, by name.
inline std::map<std::string, long long> summaryCounters(const std::string& text) {
  std::map<std::string, long long> m;
  std::smatch s;
  const std::regex cmds("commands: received (\\d+), rejected (\\d+), missed (\\d+); watchdog trips (\\d+)");
  if (std::regex_search(text, s, cmds)) {
    m["received"] = std::stoll(s[1]);
    m["rejected"] = std::stoll(s[2]);
    m["missed"] = std::stoll(s[3]);
    m["watchdog_trips"] = std::stoll(s[4]);
  }
  const std::regex timeouts("lockstep timeouts (\\d+)");
  if (std::regex_search(text, s, timeouts)) m["lockstep_timeouts"] = std::stoll(s[1]);
  const std::regex reason("rejected (\\d+): ([^\\n]+)");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), reason); it != std::sregex_iterator(); ++it) {
    m["reason: " + (*it)[2].str()] = std::stoll((*it)[1]);
  }
  return m;
}

/// A shell function for test scripts: `started FILE TEXT` waits (at most
/// 20 s) until FILE contains TEXT. The programs print their start line after
/// installing their signal handlers and opening their sockets, so a script
/// that waits for it never signals or feeds a program that is not yet up
/// (a loaded machine can take long to get there).
inline const char* kStartedFn =
    "started() { i=0; until grep -q \"$2\" \"$1\" 2>/dev/null; do i=$((i+1)); [ $i -gt 400 ] && return 1; "
    "sleep 0.05; done; }\n";

/// Quoted paths of the build's programs.
inline std::string firmwareSim() { return std::string("'") + GIMBALSIM_FIRMWARE_SIM + "'"; }
inline std::string pointingController() { return std::string("'") + GIMBALSIM_POINTING_CONTROLLER + "'"; }

}  // namespace gimbalsim::hil
