// torque_replay: a stand-in controller that answers a lockstep firmware_sim
// with the torques another run applied, tick by tick, read from that run's
// truth CSV (tau1_Nm, tau2_Nm: what acted over each tick). The plant's
// dynamics then follow the recorded run bit for bit (the CSV's numbers
// round-trip exactly; the torques are already within the limits), so its
// steps do the same work at every tick: tools/hil/worst_tick.py replays a
// real-time run in lockstep to tell a real-time tick's own cost from what
// the machine added to it. Answers status k with the torque of row k + 1 (a
// command answering status k acts from tick k + 1); tick 0 ran before any
// command in both runs. Exit 0 after answering the last status the CSV
// covers; 2 refused input; 5 network (a failed send too); 6 no plant within --idle-exit.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "gimbalsim/lcm_wire/udpm_receiver.hpp"
#include "gimbalsim/contract/channels.hpp"
#include "gimbalsim/gimbal_command_t.hpp"
#include "gimbalsim/gimbal_status_t.hpp"
#include "gimbalsim/program/program.hpp"

namespace {

using gimbalsim::program::refuse;
constexpr std::size_t kMaxRows = 2000000;  // firmware_sim --tick-log's limit: 33 min at 1 kHz

struct Torques {
  std::vector<double> tau1, tau2;  ///< [N m] applied over tick k (row k)
};

/// The two torque columns of a truth CSV written every tick (its seq column
/// 0, 1, 2, ...); throws std::runtime_error naming file, line and column.
Torques readTorques(const std::string& path) {
  // A pipe would block and a device (/dev/zero) never end: only a file is read.
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw std::runtime_error(path + (std::filesystem::exists(path, ec) ? ": not a regular file (a pipe, a device or a "
                                                                         "folder): give the truth CSV's file"
                                                                       : ": no such file"));
  }
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::string line;
  if (!std::getline(in, line)) throw std::runtime_error(path + ": empty, no header");
  std::vector<std::string> header;
  for (std::stringstream ss(line); std::getline(ss, line, ',');) header.push_back(line);
  int c1 = -1, c2 = -1, cs = -1;
  for (int j = 0; j < static_cast<int>(header.size()); ++j) {
    if (header[j] == "tau1_Nm") c1 = j;
    if (header[j] == "tau2_Nm") c2 = j;
    if (header[j] == "seq") cs = j;
  }
  if (c1 < 0 || c2 < 0 || cs < 0) {
    throw std::runtime_error(path + ":1: no seq, tau1_Nm and tau2_Nm columns (not a firmware_sim truth CSV)");
  }
  Torques t;
  for (long long n = 2; std::getline(in, line); ++n) {
    if (t.tau1.size() >= kMaxRows) throw std::runtime_error(path + ": more than 2000000 rows");
    std::vector<std::string> f;
    for (std::stringstream ss(line); std::getline(ss, line, ',');) f.push_back(line);
    // Row k must be tick k: a CSV written every N ticks (--truth-every N) would replay tick N (k + 1) as tick k + 1.
    const std::string expected = std::to_string(t.tau1.size());
    if (cs >= static_cast<int>(f.size()) || f[cs] != expected) {
      throw std::runtime_error(path + ":" + std::to_string(n) + ": seq " + (cs < static_cast<int>(f.size()) ? f[cs] : "missing") +
                               " where tick " + expected + " belongs: the CSV was not written every tick "
                               "(firmware_sim --truth-every 1)");
    }
    for (const int c : {c1, c2}) {
      char* end = nullptr;
      const double x = c < static_cast<int>(f.size()) ? std::strtod(f[c].c_str(), &end) : 0.0;
      if (c >= static_cast<int>(f.size()) || end == f[c].c_str() || *end != '\0' || !std::isfinite(x)) {
        throw std::runtime_error(path + ":" + std::to_string(n) + ": column " + header[c] + ": not a finite number");
      }
      (c == c1 ? t.tau1 : t.tau2).push_back(x);
    }
  }
  if (t.tau1.size() < 2) throw std::runtime_error(path + ": fewer than 2 rows: nothing to replay");
  return t;
}

int mainImpl(int argc, char** argv) {
  CLI::App app{"torque_replay: answers a lockstep firmware_sim with the torques of a recorded run"};
  std::string truth, url, prefix;
  double idle_exit = 10.0;
  app.add_option("truth_csv", truth, "the recorded run's firmware_sim --truth-csv (every tick)")->required();
  app.add_option("--lcm-url", url, "LCM provider URL (udpm)");
  app.add_option("--channel-prefix", prefix, "prefix of every channel name");
  app.add_option("--idle-exit", idle_exit, "wait at most this many wall seconds for a status, then exit 6")
      ->capture_default_str()->check(CLI::PositiveNumber)->check(CLI::Range(0.0, 1e6));
  if (const auto rc = gimbalsim::program::parse(app, argc, argv, "torque_replay")) return *rc;
  if (!gimbalsim::contract::Channels::validPrefix(prefix)) {
    return refuse("torque_replay", "--channel-prefix '" + prefix + "': only A-Z, 0-9 and '_' allowed");
  }
  Torques t;
  try {
    t = readTorques(truth);
  } catch (const std::runtime_error& e) {
    return refuse("torque_replay", e.what());
  }
  lcm::LCM lcm(url);
  const auto ch = gimbalsim::contract::Channels::withPrefix(prefix);
  gimbalsim::lcm_wire::UdpmReceiver rx({}, gimbalsim::lcm_wire::ChannelFilter({ch.status}));
  if (std::string why; !lcm.good() || !rx.open(url, 1 << 20, &why)) {
    std::fprintf(stderr, "torque_replay: network: %s\n", lcm.good() ? why.c_str() : "LCM could not start");
    return gimbalsim::program::kNetwork;
  }
  const auto last = static_cast<std::int64_t>(t.tau1.size()) - 2;  // the last status that has a next row
  std::int64_t answered = -1, seq = 0;
  std::int64_t heard_ns = gimbalsim::lcm_wire::monotonicNs();
  bool sent = true;
  while (answered < last && sent) {
    if (rx.wait(100, 0) < 0) return gimbalsim::program::kNetwork;
    rx.drain([&](const gimbalsim::lcm_wire::Message& m, std::int64_t) {
      gimbalsim::gimbal_status_t st{};
      if (!sent) return;
      if (st.decode(m.data, 0, static_cast<int>(m.size)) != static_cast<int>(m.size)) return;
      heard_ns = gimbalsim::lcm_wire::monotonicNs();
      if (st.seq <= answered || st.seq > last) return;  // a repeat (status 0 is re-sent until answered), or past the CSV
      gimbalsim::gimbal_command_t c{};
      c.utime = st.utime;
      c.seq = seq++;
      c.status_seq = st.seq;
      c.mode = gimbalsim::gimbal_command_t::MODE_TORQUE;
      c.torque[0] = t.tau1[static_cast<std::size_t>(st.seq) + 1];
      c.torque[1] = t.tau2[static_cast<std::size_t>(st.seq) + 1];
      sent = lcm.publish(ch.command, &c) == 0;  // a lost answer would stall the plant: stop and say so
      answered = st.seq;
    }, 256);
    if (static_cast<double>(gimbalsim::lcm_wire::monotonicNs() - heard_ns) * 1e-9 > idle_exit) {
      std::fprintf(stderr, "torque_replay: no status for %g s after status %lld\n", idle_exit,
                   static_cast<long long>(answered));
      return gimbalsim::program::kNoPeer;
    }
  }
  if (!sent) {
    std::fprintf(stderr, "torque_replay: publishing the answer to status %lld failed\n", static_cast<long long>(answered));
    return gimbalsim::program::kNetwork;
  }
  std::fprintf(stderr, "torque_replay: answered statuses 0..%lld from %s\n", static_cast<long long>(last), truth.c_str());
  return gimbalsim::program::kOk;
}

}  // namespace

int main(int argc, char** argv) {
  return gimbalsim::program::guardedMain("torque_replay", [&] { return mainImpl(argc, argv); });
}
