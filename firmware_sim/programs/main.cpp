// firmware_sim: the gimbal plant as a process that speaks LCM like the
// gimbal's firmware. This file parses the options, loads the scene and the
// profile, checks the settings and wires the pieces: lcm_bridge (LCM in and
// out), realtime_loop / lockstep_loop (the two modes), truth_csv
// (--truth-csv), summary (exit summary and plant fault). CLI: docs/usage.md;
// exit codes: gimbalsim/program/program.hpp.
#include <CLI/CLI.hpp>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "app.hpp"
#include "gimbalsim/lcm_wire/udpm_receiver.hpp"
#include "gimbalsim/program/program.hpp"
#include "gimbalsim/contract/channels.hpp"
#include "gimbalsim/firmware_sim/plant_scene.hpp"
#include "gimbalsim/firmware_sim/study_idle.hpp"
#include "gimbalsim/dynamics/simulate.hpp"
#include "gimbalsim/firmware_sim/fault_schedule_io.hpp"
#include "gimbalsim/input/key_registry.hpp"
#include "lcm_bridge.hpp"
#include "gimbalsim/pointing/profile_keys.hpp"
#include "realtime.hpp"
#include "tick_budget.hpp"
#include "tick_log.hpp"
#include "truth_csv.hpp"

namespace gimbalsim::firmware {

std::atomic<bool> g_stop{false};

namespace {

constexpr int kRecvBufferBytes = 4 << 20;  ///< socket receive buffer asked for: rides out a burst [bytes]

int refuse(const std::string& what) { return program::refuse("firmware_sim", what); }

/// Parse: the options (docs/usage.md "firmware_sim").
void addOptions(CLI::App& app, Options& o) {
  app.add_option("scene", o.scene, "scene file (YAML), e.g. tools/scenes/paper_clearance.yaml")->required();
  app.add_option("--set", o.sets, "scene override key=value (repeatable); see `gimbalsim keys`");
  app.add_option("--rate", o.rate_hz, "control rate [Hz]; 1/rate must be a whole multiple of sim.step")
      ->capture_default_str()->check(program::within(1e-3, 1e6));
  // Upper bounds on every time: each becomes an int64 count of ticks or ns (no overflow).
  app.add_option("--duration", o.duration, "simulated seconds to run (0 = until SIGINT/SIGTERM)")
      ->capture_default_str()->check(program::within(0.0, 1e9));
  app.add_flag("--lockstep", o.lockstep, "lockstep: tick k+1 waits for the command answering status k");
  // The waits are counted in the receive's whole milliseconds: a shorter one (1e-300) ran as no wait at all.
  app.add_option("--lockstep-timeout-ms", o.lockstep_timeout_ms, "lockstep: wait at most this for an answer [ms]")
      ->capture_default_str()->check(program::within(1.0, 1e9));
  app.add_option("--start-timeout", o.start_timeout_s, "lockstep: wait at most this for the first answer [s]")
      ->capture_default_str()->check(program::within(1e-3, 1e6));
  app.add_option("--truth-every", o.truth_every, "publish truth every N ticks")
      ->capture_default_str()->check(program::wholeNumber())->check(CLI::Range(1, 1000000000));
  app.add_option("--truth-csv", o.truth_csv, "write every truth message to this CSV file");
  app.add_option("--tick-log", o.tick_log, "write each tick's sub-steps, derivatives and compute times (CPU and wall) "
                 "to this CSV file after the run (needs --duration; at most 2e6 ticks)");
  app.add_option("--lcm-url", o.lcm_url, "LCM provider URL (default: LCM_DEFAULT_URL or LCM's default)")
      ->check(CLI::Validator(gimbalsim::lcm_wire::lcmUrlProblem, "URL"));
  app.add_option("--channel-prefix", o.prefix, "prefix of every channel name, e.g. BENCH2_");
  app.add_option("--rt-priority", o.rt_priority, "SCHED_FIFO priority of the loop thread (0 = SCHED_OTHER)")
      ->capture_default_str()->check(program::wholeNumber())->check(CLI::Range(0, 99));
  app.add_option("--cpu", o.cpu, "real time: pin the loop thread to this CPU and keep the communication thread off it "
                 "(-1 = no pin)")->capture_default_str()->check(program::wholeNumber())->check(CLI::Range(-1, 1023));
  app.add_option("--spin-us", o.spin_us, "real time: busy-wait the last US before each deadline; lockstep: "
                 "busy-poll up to US for the answer before sleeping [us, at most 100000]")
      ->capture_default_str()->check(program::within(0.0, 100000.0));
  app.add_option("--cpu-dma-latency-us", o.cpu_dma_latency_us, "hold idle CPUs to this wake-up latency for the run "
                 "(/dev/cpu_dma_latency, as cyclictest does; 0 = idle by polling, -1 = do not ask; lockstep too: a "
                 "CPU that halts between ticks comes back slower than the tick budget was timed) [us, at most 1000000]")
      ->capture_default_str()->check(program::wholeNumber())->check(CLI::Range(-1, 1000000));
  app.add_option("--watchdog-ms", o.watchdog_ms, "no valid command for this long -> safe command [ms]")
      ->capture_default_str()->check(program::within(0.0, 1e9, true));
  app.add_option("--torque-sanity", o.torque_sanity, "reject commands with |torque| > this x torque.limit")
      ->capture_default_str()->check(program::within(1.0, 1e6));
  app.add_option("--safe-torque", o.safe_torque, "torque applied while the watchdog is tripped [N m] (2 values)")
      ->expected(2)->capture_default_str();
  app.add_option("--profile", o.profile, "a pointing_controller config whose profile keys (its profile: section, or flat profile.* keys) define "
                 "the pointing error");
  app.add_option("--stats-period", o.stats_period, "loop statistics publication period [s]")
      ->capture_default_str()->check(program::within(0.0, 1e6, true));
  app.add_option("--faults", o.faults, "fault schedule file (YAML, docs/bench.md \"Fault schedule\"), e.g. tools/faults/demo.yaml");
}

/// What a run reads before it starts: the plant, the firmware's settings, the
/// optional profile and fault schedule.
struct Inputs {
  PlantScene plant;
  Config c;
  std::unique_ptr<pointing::TargetProfile> profile;
  FaultSchedule faults;
};

/// The first --set the bench never reads, or "": it would be recorded with the run and act on nothing (pass 86:
/// torque.tau1, sim.duration and a tracker's noise without a tracker ran silently). The name is printed: read.
std::string idleBenchOverride(const Options& o, const Inputs& in) {
  const double duration_s = o.duration > 0.0 ? o.duration : std::numeric_limits<double>::infinity();
  const SensorParams& sensors = in.plant.sensors;
  for (std::size_t k = 0; k < o.sets.size(); ++k) {
    const std::string key = o.sets[k].substr(0, o.sets[k].find('='));
    // the name is printed in the summary: read
    std::string why = key == "sim.duration" ? "firmware_sim runs --duration (or until stopped)"
                      : key == "name"       ? ""
                                            : closedLoopIdleSceneKey(key);
    const SensorRun run{duration_s, 1.0 / o.rate_hz, true, in.plant.scene.model.floating_base, &in.faults};
    if (why.empty()) why = sensorKeyIdle(key, sensors, run);
    if (why.empty() && key == "sensors.seed" && !sensors.anyNoise()) why = "the scene's sensors draw no noise";
    if (!why.empty()) {
      return "--set #" + std::to_string(k + 1) + " '" + o.sets[k] + "': not read by the bench (" + why +
             "): the value would be recorded but never act";
    }
  }
  return "";
}

/// Loads and checks the inputs and opens the outputs; kExitOk, or the refusal's code (nothing run).
int loadInputs(const Options& o, Inputs& in, TruthCsv& csv, TickLog& tick_log) {
  try {
    in.plant = loadPlantScene(o.scene, closedLoopOverrides(o.sets));
  } catch (const InputError& e) {
    for (const std::string& p : e.problems()) std::fprintf(stderr, "error: %s\n", p.c_str());
    return refuse("scene " + o.scene + " refused");
  }
  const Scene& scene = in.plant.scene;
  for (const std::string& w : scene.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());

  Config& c = in.c;
  c.control_period = 1.0 / o.rate_hz;
  c.watchdog_timeout = o.watchdog_ms * 1e-3;
  c.torque_sanity_factor = o.torque_sanity;
  c.safe_torque = Vec2(o.safe_torque[0], o.safe_torque[1]);
  if (const ConfigCheck chk = checkConfig(scene, c); !chk.ok()) {
    // Each setting is a flag's (the period is 1 / --rate): the refusal names the flag as given.
    using S = ConfigCheck::Setting;
    const char* flag = chk.wrong == S::ControlPeriod        ? "--rate"
                       : chk.wrong == S::WatchdogTimeout    ? "--watchdog-ms"
                       : chk.wrong == S::TorqueSanityFactor ? "--torque-sanity"
                                                            : "--safe-torque";
    const std::string given = chk.wrong == S::ControlPeriod ? " " + CLI::detail::to_string(o.rate_hz) : "";
    return refuse(flag + given + ": " + chk.message);
  }
  // The loop runs whole control periods: a duration between two is refused, never rounded.
  if (const std::string why = wholeMultipleProblem(o.duration, c.control_period, "the control period (1 / --rate)");
      o.duration != 0.0 && !why.empty()) {
    return refuse("--duration " + CLI::detail::to_string(o.duration) + ": " + why);
  }
  // (pass 103) statistics go out at most once a tick: 1e-9 s was taken and ran as one tick
  if (o.stats_period < c.control_period * (1.0 - 1e-9)) {
    return refuse("--stats-period " + CLI::detail::to_string(o.stats_period) + ": below one control period (1 / " +
                  "--rate = " + formatNumber(c.control_period) + " s); the statistics go out at most once a tick");
  }
  if (const std::string why = Channels::prefixProblem(o.prefix); !why.empty()) {
    return refuse("--channel-prefix '" + o.prefix + "': " + why);
  }
  if (!o.profile.empty()) {
    try {
      in.profile = std::make_unique<pointing::TargetProfile>(pointing::loadTargetProfile(o.profile));
    } catch (const InputError& e) {
      for (const std::string& p : e.problems()) std::fprintf(stderr, "error: %s\n", p.c_str());
      return refuse("--profile " + o.profile + " refused");
    }
  }
  if (!o.faults.empty()) {
    try {
      in.faults = loadFaultSchedule(o.faults);
    } catch (const InputError& e) {
      for (const std::string& p : e.problems()) std::fprintf(stderr, "error: %s\n", p.c_str());
      return refuse("--faults " + o.faults + " refused");
    }
    if (const auto problems = checkFaultsAgainstScene(in.faults, in.plant, o.faults); !problems.empty()) {
      for (const std::string& p : problems) std::fprintf(stderr, "error: %s\n", p.c_str());
      return refuse("--faults " + o.faults + " refused for scene " + o.scene);
    }
    // a run without --duration has no end: only its ticks can leave a fault idle
    auto late = checkFaultsAgainstDuration(in.faults, o.duration > 0.0 ? o.duration : kForever, 1.0 / o.rate_hz,
                                           o.faults);
    if (late.empty()) {
      late = checkFaultsAgainstSamples(in.faults, in.plant, o.duration > 0.0 ? o.duration : kForever,
                                       1.0 / o.rate_hz, o.faults, false);
    }
    if (!late.empty()) {
      for (const std::string& p : late) std::fprintf(stderr, "error: %s\n", p.c_str());
      return refuse("--faults " + o.faults + " refused for --rate " + formatNumber(o.rate_hz) +
                    (o.duration > 0.0 ? " and --duration " + formatNumber(o.duration) : std::string()));
    }
  }
  // after the schedule: its gyro_bias_jump makes the star tracker's keys act on a fixed base
  if (const std::string why = idleBenchOverride(o, in); !why.empty()) return refuse(why);
  const std::vector<std::string> inputs{o.scene, o.profile, o.faults};
  // A path no output may take (a link, a folder, an input, both outputs one file) or a tick log
  // the run cannot hold is refused (exit 2); a folder that takes no file could not be written (4).
  for (const auto& [flag, path] : {std::pair{"--truth-csv", o.truth_csv}, {"--tick-log", o.tick_log}}) {
    try {
      io::checkOutputPaths({path}, inputs);
    } catch (const io::OutputError& e) {
      return refuse(std::string(flag) + ": " + e.what());
    }
  }
  try {
    io::checkOutputPaths({o.truth_csv, o.tick_log});  // each alone passed above; not one file for both
  } catch (const io::OutputError& e) {
    return refuse(std::string("--truth-csv and --tick-log: ") + e.what());
  }
  if (const std::string why = TickLog::boundsProblem(totalTicks(o, c)); !o.tick_log.empty() && !why.empty()) {
    return refuse("--tick-log: " + why);
  }
  const bool antenna = in.plant.sensors.antenna_sensors;  // its columns follow the truth's
  const auto unwritable = [](const std::string& what) { return program::unwritable("firmware_sim", what); };
  if (std::string why; !o.truth_csv.empty() && !csv.open(o.truth_csv, inputs, &why, antenna)) {
    return unwritable("--truth-csv: " + why);
  }
  if (std::string why; !o.tick_log.empty() && !tick_log.open(o.tick_log, totalTicks(o, c), inputs, &why)) {
    return unwritable("--tick-log: " + why);
  }
  return kExitOk;
}

/// Run: LCM up, the loop, the outputs committed together; the exit code.
int runBench(const Options& o, Inputs& in, TruthCsv& csv, TickLog& tick_log) {
  const Scene& scene = in.plant.scene;
  const Model& m = scene.model;
  const Config& c = in.c;
  const std::unique_ptr<pointing::TargetProfile>& profile = in.profile;
  const FaultSchedule& faults = in.faults;
  const CpuLatencyRequest cpu_latency(o.cpu_dma_latency_us);
  if (!o.lockstep) {
    if (const std::string w = lockMemory(); !w.empty()) std::fprintf(stderr, "firmware_sim: %s\n", w.c_str());
  }
  if (!cpu_latency.warning().empty()) std::fprintf(stderr, "firmware_sim: %s\n", cpu_latency.warning().c_str());
  if (cpu_latency.held()) {
    std::fprintf(stderr, "firmware_sim: idle CPUs held to %d us of wake-up latency while this runs (machine-wide, "
                 "/dev/cpu_dma_latency; --cpu-dma-latency-us -1 to not ask)\n", o.cpu_dma_latency_us);
  }
  // Sending and receiving are ours (lcm_wire), not liblcm's: LCM 1.3.1's receive
  // thread crashes on malformed fragments and queues 30 messages per subscription,
  // and its publish costs a system call per message (udpm_sender.hpp).
  lcm_wire::UdpmSender tx;
  if (std::string why; !tx.open(o.lcm_url, &why)) {
    std::fprintf(stderr, "firmware_sim: error: LCM could not start: %s (check --lcm-url / LCM_DEFAULT_URL)\n",
                 why.c_str());
    return kExitLcm;
  }
  const Channels channels = Channels::withPrefix(o.prefix);
  lcm_wire::UdpmReceiver rx(LcmBridge::receiveLimits(), lcm_wire::ChannelFilter({channels.command}));
  if (std::string why; !rx.open(o.lcm_url, kRecvBufferBytes, &why)) {
    std::fprintf(stderr, "firmware_sim: error: cannot receive: %s\n", why.c_str());
    return kExitLcm;
  }
  LcmBridge bridge(tx, rx, channels);

  std::fprintf(stderr, "firmware_sim: scene '%s' (%s), %g Hz (%d RK4 steps of %g s per tick), %s, channels %s*\n",
               m.name.c_str(), variantName(m).c_str(), o.rate_hz, static_cast<int>(std::llround(c.control_period / m.integrator.step)),
               m.integrator.step, o.lockstep ? "lockstep" : "real time", (o.prefix + "GIMBAL_").c_str());

  const TickBudget budget = measureTickBudget(scene, c);
  Run r{.setup = {.plant = in.plant,
                  .o = o,
                  .c = c,
                  .profile = profile.get(),
                  .faults = faults.empty() ? nullptr : &faults,
                  .worst_tick_us = budget.worst_tick_us,
                  .worst_tick_derivatives = static_cast<long long>(budget.steps_per_tick) * budget.substep_cap *
                                            budget.evals_per_substep},
        .ports = {.bridge = bridge, .csv = csv, .tick_log = tick_log},
        .report = {}};
  // Say which target the truth pointing error is measured against.
  if (profile) {
    std::fprintf(stderr, "firmware_sim: truth pointing error against the profile: section of %s (tracking from "
                 "t = %g s)\n", o.profile.c_str(), profile->trackStart());
  } else {
    std::fprintf(stderr, "firmware_sim: truth pointing error against the boresight at t = 0, a fixed direction (no "
                 "--profile); give --profile CONFIG for the controller's target\n");
  }
  std::fprintf(stderr, "firmware_sim: %s\n", describeTickBudget(budget).c_str());
  if (const std::string w = tickBudgetWarning(budget); !w.empty()) std::fprintf(stderr, "firmware_sim: %s\n", w.c_str());
  if (!faults.empty()) {
    std::fprintf(stderr, "firmware_sim: fault schedule %s: %zu faults, seed %llu\n", o.faults.c_str(),
                 faults.faults.size(), static_cast<unsigned long long>(faults.seed));
  }
  const int rc = o.lockstep ? runLockstep(r) : runRealtime(r);
  if (r.report.unanswered_start) {
    // No controller took part: the outputs would hold tick 0 alone, over the previous run's (pass 82).
    for (const auto& [flag, path] : {std::pair{"--truth-csv", o.truth_csv}, {"--tick-log", o.tick_log}}) {
      if (path.empty()) continue;
      std::fprintf(stderr, "firmware_sim: %s: nothing written (no command answered status 0): %s is as it was\n",
                   flag, path.c_str());
    }
    return rc;
  }
  // The outputs appear together or not at all (a failed write leaves neither under its name).
  io::CommitGroup outputs({csv.file(), tick_log.file()});
  if (std::string why; !tick_log.writeRows(&why) || !outputs.commit()) {
    std::fprintf(stderr, "firmware_sim: error: %s\n", why.empty() ? outputs.error().c_str() : why.c_str());
    return rc == kExitOk ? kExitOutput : rc;
  }
  // Stopped by SIGINT/SIGTERM/SIGHUP, outputs whole: 128 + the signal, and said (pass 72: only the tick count
  // showed that a 30 s run had ended at 1.5 s).
  if (rc == kExitOk && io::stopRequested()) {
    std::fprintf(stderr, "firmware_sim: interrupted by %s; the outputs hold the ticks run\n", io::stopSignalName());
    return io::stopExitCode();
  }
  return rc;
}

int mainImpl(int argc, char** argv) {
  Options o;
  CLI::App app{"firmware_sim: the gimbal plant speaking LCM like its firmware (real time or lockstep)"};
  addOptions(app, o);
  if (const auto rc = program::parse(app, argc, argv, "firmware_sim")) return *rc;
  if (const std::string why = lcm_wire::defaultLcmUrlProblem(o.lcm_url); !why.empty()) {
    return program::refuse("firmware_sim", why);
  }
  // (pass 111) the watchdog counts whole ticks: 1e-9 ms ran as one tick (1 ms), 1.5 as two, without a word
  if (app.count("--watchdog-ms") > 0 && !isWholeMultiple(o.watchdog_ms * 1e-3, 1.0 / o.rate_hz)) {
    const double tick_ms = 1e3 / o.rate_hz, k = std::floor(o.watchdog_ms / tick_ms);
    return program::refuse("firmware_sim", "--watchdog-ms " + formatNumber(o.watchdog_ms) + ": not a whole number "
                           "of control periods (" + formatNumber(tick_ms) + " ms at --rate " + formatNumber(o.rate_hz) +
                           "), which the watchdog counts: " + (k >= 1 ? formatNumber(k * tick_ms) + " or " : "") +
                           formatNumber((k + 1) * tick_ms) + " ms");
  }
  if (!o.lockstep && o.cpu >= 0) {  // a CPU the process may not use is the user's slip, not the OS's refusal
    if (const std::string why = cpuProblem(o.cpu); !why.empty()) return program::refuse("firmware_sim", why);
  }
  // A flag of the other mode would be recorded with the run and act on nothing (pass 91: lockstep warned and
  // ran, real time took the lockstep waits silently): refused. Lockstep runs one thread, no deadlines, no
  // real-time set-up (--rt-priority 0, SCHED_OTHER, is what it does).
  if (o.lockstep && app.count("--cpu") > 0) {
    return program::refuse("firmware_sim", "--cpu applies to real time only: lockstep runs one thread unpinned");
  }
  if (o.lockstep && app.count("--rt-priority") > 0 && o.rt_priority != 0) {
    return program::refuse("firmware_sim", "--rt-priority " + std::to_string(o.rt_priority) +
                                               ": applies to real time only: lockstep runs SCHED_OTHER (0)");
  }
  for (const char* flag : {"--lockstep-timeout-ms", "--start-timeout"}) {
    if (!o.lockstep && app.count(flag) > 0) {
      return program::refuse("firmware_sim", std::string(flag) + " applies to lockstep only (--lockstep): a real-time "
                                                                 "run waits for no answer");
    }
  }
  // sigaction without SA_RESTART: a blocking wait returns at once (EINTR); the loops see g_stop.
  // Before the outputs' temporaries exist: a signal during set-up left them behind.
  io::installStopHandlers([] { g_stop.store(true); });
  Inputs in;
  TruthCsv csv;
  TickLog tick_log;
  if (const int rc = loadInputs(o, in, csv, tick_log); rc != kExitOk) return rc;
  return runBench(o, in, csv, tick_log);
}

}  // namespace
}  // namespace gimbalsim::firmware

int main(int argc, char** argv) {
  return gimbalsim::program::guardedMain("firmware_sim", [&] { return gimbalsim::firmware::mainImpl(argc, argv); });
}
