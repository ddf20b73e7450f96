// firmware_sim's pieces and how main.cpp wires them: the options, the exit
// codes, the hand-over between the LCM side and the loop, and the context
// (Run) that both loops take. CLI: docs/usage.md; exit codes: program.hpp.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "gimbalsim/dynamics/run_spec.hpp"
#include "gimbalsim/firmware_sim/firmware.hpp"
#include "gimbalsim/firmware_sim/observed_truth.hpp"
#include "gimbalsim/firmware_sim/spsc_ring.hpp"
#include "gimbalsim/program/program.hpp"
#include "loop_stats.hpp"

namespace lcm {
class LCM;
}

namespace gimbalsim::firmware {

/// The exit codes, named for firmware_sim: the one table (program.hpp, docs/usage.md "Exit codes").
enum ExitCode : int {
  kExitOk = program::kOk,
  kExitInternal = program::kInternal,      ///< unexpected exception (a bug)
  kExitRefused = program::kRefused,        ///< bad flag, scene, profile or output file: nothing run
  kExitPlantFault = program::kStopped,     ///< the plant stopped on numerical trouble during the run
  kExitLcm = program::kNetwork,            ///< LCM could not start (bad --lcm-url, no multicast route)
  kExitNoController = program::kNoPeer,    ///< lockstep: nobody answered status 0 within --start-timeout
  kExitOutput = program::kOutput,          ///< an output file could not be written (the run stopped; the target is untouched)
};

/// Set by SIGINT/SIGTERM (and by a failed write); the loops check it every tick.
extern std::atomic<bool> g_stop;

struct Options {
  std::string scene;
  std::vector<std::string> sets;
  double rate_hz = 1000.0;
  double duration = 0.0;
  bool lockstep = false;
  double lockstep_timeout_ms = 1000.0;
  double start_timeout_s = 30.0;
  int truth_every = 1;
  std::string truth_csv;
  std::string tick_log;  ///< --tick-log CSV, "" = none
  std::string lcm_url;
  std::string prefix;
  int rt_priority = 80;
  int cpu = -1;
  double spin_us = 0.0;
  int cpu_dma_latency_us = 0;  ///< [us] PM QoS CPU latency request held for the run (-1: none)
  double watchdog_ms = 50.0;
  double torque_sanity = 10.0;
  std::vector<double> safe_torque{0.0, 0.0};
  std::string profile;
  double stats_period = 1.0;
  std::string faults;  ///< fault schedule file (--faults), "" = none
};

/// A command as it crosses from the communication thread to the loop.
struct Inbound {
  bool undecodable = false;
  Command cmd;
  SourceId source = kInProcessSource;  ///< the sender (bench_io::Source::id())
};

/// What the loop hands back each tick.
struct Outbound {
  Attitude attitude;
  bool has_status = true;  ///< false: a scheduled status drop or delay left none this tick
  Status status;
  bool has_truth = false;
  Truth truth;
};

class LcmBridge;
class TruthCsv;
class TickLog;

/// The truth pointing error over the truths of a run, and while tracking (the
/// profile's Track segment); added by the loop thread, no allocation.
struct PointingErrorStats {
  double max_rad = 0.0, sum_sq = 0.0, last_rad = 0.0;  ///< [rad], [rad^2]
  long long n = 0;
  double max_track_rad = 0.0, sum_sq_track = 0.0;
  long long n_track = 0;
  void add(double e_rad, bool tracking) noexcept {
    max_rad = e_rad > max_rad ? e_rad : max_rad;
    sum_sq += e_rad * e_rad;
    last_rad = e_rad;
    ++n;
    if (tracking) {
      max_track_rad = e_rad > max_track_rad ? e_rad : max_track_rad;
      sum_sq_track += e_rad * e_rad;
      ++n_track;
    }
  }
};

/// Everything a loop needs; main.cpp builds it.
struct Run {
  const PlantScene& plant;
  const Options& o;
  const Config& c;
  const pointing::TargetProfile* profile;  ///< null: target = boresight at t = 0
  lcm::LCM& lcm;
  LcmBridge& bridge;
  SpscRing<Inbound>& in;
  TruthCsv& csv;
  TickLog& tick_log;  ///< --tick-log (filled by the loop thread, written after the run)
  LoopStats stats;
  bool fifo = false;
  std::vector<std::string> rt_warnings;
  double wall_seconds = 0.0;
  long long lockstep_timeouts = 0;
  const FaultSchedule* faults = nullptr;  ///< --faults, null = none
  double worst_tick_us = 0.0;  ///< [us] the sub-step cap's bound on a tick (tick_budget.hpp), measured at start
  long long worst_tick_derivatives = 0;  ///< the bound's count: derivative evaluations of one tick's stepping at most
  double compute_seconds = 0.0;  ///< [s] wall time of the plant's own work (ticks, not the waits)
  PointingErrorStats pointing;   ///< the truth pointing error (written by the loop, read after it)
};

/// Ticks to run: --duration / T, or -1 (until stopped).
inline std::int64_t totalTicks(const Options& o, const Config& c) {
  return o.duration > 0.0 ? static_cast<std::int64_t>(std::llround(o.duration / c.control_period)) : -1;
}

/// Hands every queued command to the firmware; *answered becomes true when an
/// accepted one answers status `answer_to` (lockstep: a rejected command,
/// e.g. a spoof or a NaN torque, never releases the gate).
template <class V>
void drainInbound(Firmware<V>& fw, SpscRing<Inbound>& in, std::int64_t answer_to = -2, bool* answered = nullptr) {
  Inbound m;
  while (in.pop(m)) {
    if (m.undecodable) {
      fw.receiveUndecodable();
    } else {
      const Rejection r = fw.receive(m.cmd, m.source);
      if (answered && r == Rejection::None && m.cmd.status_seq == answer_to) *answered = true;
    }
  }
}

/// Steps a scratch copy of the plant a few times and drops it, just before
/// the first tick: the first tick would otherwise pay for code run for the
/// first time and cold caches (measured in lockstep: 1.8-2.6 us against a
/// 1.1 us tick), which the bound's cold-cache term does not cover.
template <class V>
void warmUp(const Firmware<V>& fw) noexcept {
  State<V> s = fw.state();
  Data<V> d(fw.model());
  for (int i = 0; i < 3 && step(fw.model(), d, s, fw.appliedInput()).ok(); ++i) {
  }
}

/// The real-time loop (realtime_loop.cpp) and the lockstep loop
/// (lockstep_loop.cpp); each returns the exit code.
int runRealtime(Run& r);
int runLockstep(Run& r);

}  // namespace gimbalsim::firmware
