// firmware_sim's pieces and how main.cpp wires them: the options, the exit
// codes, the hand-over of commands from the LCM side, and the run (setup,
// ports, report) that both loops take. CLI: docs/usage.md; exit codes: program.hpp.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "gimbalsim/dynamics/run_spec.hpp"
#include "gimbalsim/firmware_sim/firmware.hpp"
#include "gimbalsim/firmware_sim/bench_tick.hpp"
#include "gimbalsim/program/program.hpp"
#include "loop_stats.hpp"
#include "tick_log.hpp"

namespace gimbalsim::firmware {

/// The exit codes, named for firmware_sim: the project's table (docs/usage.md "Exit codes", mirrored in program.hpp).
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

/// A command as it crosses from the bridge to the firmware.
struct Inbound {
  bool undecodable = false;
  Command cmd;
  SourceId source = kInProcessSource;  ///< the sender (lcm_wire::Source::id())
};

/// Where the bridge puts each decoded command: the ring to the loop thread
/// (real time) or the firmware itself (lockstep, one thread). False: dropped.
class CommandSink {
 public:
  virtual bool take(const Inbound& m) noexcept = 0;

 protected:
  ~CommandSink() = default;
};

class LcmBridge;
class TruthCsv;

/// What a run is given (main.cpp builds it).
struct RunSetup {
  const PlantScene& plant;
  const Options& o;
  const Config& c;
  const pointing::TargetProfile* profile = nullptr;  ///< null: target = boresight at t = 0
  const FaultSchedule* faults = nullptr;             ///< --faults, null = none
  double worst_tick_us = 0.0;  ///< [us] the sub-step cap's bound on a tick (tick_budget.hpp), measured at start
  long long worst_tick_derivatives = 0;  ///< the bound's count: derivative evaluations of one tick's stepping at most
};

/// The run's transport and files: LCM out and in, the truth CSV, the tick log.
struct BenchPorts {
  LcmBridge& bridge;
  TruthCsv& csv;
  TickLog& tick_log;  ///< --tick-log (filled by the loop thread, written after the run)
};

/// What the loop measured, read by the exit summary.
struct RunReport {
  LoopStats stats;
  bool fifo = false;
  std::vector<std::string> rt_warnings;
  double wall_seconds = 0.0;
  long long lockstep_timeouts = 0;
  long long lockstep_rebinds = 0;  ///< bindings released: the bound controller silent while another answered
  double compute_seconds = 0.0;  ///< [s] wall time of the plant's own work (ticks, not the waits)
  PointingErrorStats pointing;   ///< the truth pointing error (copied from the tick at the end)
  bool unanswered_start = false;  ///< lockstep: ended at status 0, which no command reached: no run, no output
};

/// Everything a loop needs, in three named parts.
struct Run {
  RunSetup setup;
  BenchPorts ports;
  RunReport report;
};

/// Ticks to run: --duration / T, or -1 (until stopped).
inline std::int64_t totalTicks(const Options& o, const Config& c) {
  return o.duration > 0.0 ? static_cast<std::int64_t>(std::llround(o.duration / c.control_period)) : -1;
}

/// Hands one command to the firmware, as it arrived; true when accepted.
template <class V>
bool deliver(Firmware<V>& fw, const Inbound& m) noexcept {
  if (m.undecodable) {
    fw.receiveUndecodable();
    return false;
  }
  return fw.receive(m.cmd, m.source) == Rejection::None;
}

/// Steps a scratch copy of the plant a few times and drops it, just before
/// the first tick: the first tick would otherwise pay for code run for the
/// first time and cold caches, which the bound's cold-cache term does not cover.
template <class V>
void warmUp(const Firmware<V>& fw) noexcept {
  State<V> s = fw.state();
  Data<V> d(fw.model());
  for (int i = 0; i < 3 && step(fw.model(), d, s, fw.appliedInput()).ok(); ++i) {
  }
}

/// One tick's clock readings [ns]: wall time (CLOCK_MONOTONIC) and the loop
/// thread's CPU time, at the tick's start, before its step and at its end.
struct TickTimes {
  std::int64_t wall_start, cpu_start, cpu_step, cpu_end, wall_end;
};

/// Adds tick k's times to the report and the tick log: loop thread, no allocation.
template <class V>
void account(Run& r, const Firmware<V>& fw, std::int64_t k, const TickTimes& t) noexcept {
  const std::int64_t wall_ns = t.wall_end - t.wall_start;
  r.report.stats.compute.add(static_cast<double>(wall_ns) * 1e-3);
  r.report.stats.addComputeCpu(k, static_cast<double>(t.cpu_end - t.cpu_start) * 1e-3,
                               static_cast<double>(t.cpu_end - t.cpu_step) * 1e-3, fw.lastSubsteps());
  r.ports.tick_log.add(tickRecord(fw, t.cpu_end - t.cpu_step, t.cpu_end - t.cpu_start, wall_ns));
  r.report.compute_seconds += static_cast<double>(wall_ns) * 1e-9;
  r.report.stats.addTick(k + 1, fw.lastSubsteps());
}

/// The real-time loop (realtime_loop.cpp) and the lockstep loop
/// (lockstep_loop.cpp); each returns the exit code.
int runRealtime(Run& r);
int runLockstep(Run& r);

}  // namespace gimbalsim::firmware
