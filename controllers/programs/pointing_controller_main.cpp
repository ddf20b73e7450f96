// pointing_controller: the controller library on the other side of LCM. It
// subscribes to the gimbal status and answers EVERY status at once with one
// torque command whose status_seq is that status's seq (this is what lets
// firmware_sim --lockstep advance). Profile time is seq * control.period, the
// plant's simulated time, so the controller may join a running bench. The
// attitude message (GIMBAL_ATTITUDE, published just before the status of the
// same tick) is kept; the status uses it when the seqs match, else the gyro
// sample counts as missing (answerStatus), exactly as the in-process loop.
// The status handler (status_handler.hpp) answers each status without
// allocating. Receiving is our bounded UDP receiver
// (lcm_wire/udpm_receiver.hpp), not LCM's receive thread, which LCM 1.3.1
// lets crash on one malformed fragment.
// Flags: docs/usage.md; exit codes: the project's table (docs/usage.md "Exit codes", mirrored in program.hpp).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <optional>
#include <vector>

#include "gimbalsim/io/csv_format.hpp"
#include "gimbalsim/io/output_file.hpp"
#include "gimbalsim/lcm_wire/peak_memory.hpp"
#include "gimbalsim/lcm_wire/udpm_receiver.hpp"

#include "gimbalsim/program/program.hpp"
#include "gimbalsim/contract/channels.hpp"
#include "gimbalsim/contract/messages.hpp"
#include "gimbalsim/controllers/answer.hpp"
#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/controllers/key_use.hpp"
#include "gimbalsim/input/key_registry.hpp"
#include "gimbalsim/pointing/profile_windows.hpp"
#include "gimbalsim/gimbal_attitude_t.hpp"
#include "gimbalsim/gimbal_command_t.hpp"
#include "gimbalsim/gimbal_status_t.hpp"
#include "status_handler.hpp"

namespace gimbalsim::controllers {
namespace {

/// The status after a command reports it (lockstep and real time).
using contract::kStatusesToJudge;

struct Options {
  std::string config;
  std::vector<std::string> sets;
  std::string lcm_url;
  std::string prefix;
  double duration = 0.0;   ///< [s] of a run (firmware_sim --duration); 0 = until SIGINT/SIGTERM
  double idle_exit = 0.0;  ///< [s] of wall time waiting for the first status; 0 = forever
  double plant_timeout = 3.0;  ///< [s] of wall time without a status after the first: the plant has gone; 0 = never
  std::string log_csv;
  double spin_us = 0.0;  ///< [us] busy-poll for the next status before sleeping (lockstep benches)
  bool keys = false;
  bool markdown = false;  ///< --keys as a Markdown table
  bool print_config = false;
};

int run(int argc, char** argv) {
  CLI::App app{"Pointing controller: answers every gimbal status with a torque command over LCM"};
  Options o;
  app.add_option("config", o.config,
                 "controller configuration (YAML): gains, limits, profile (default: the built-in default "
                 "configuration, the values of controllers/config/default.yaml)");
  app.add_option("--set", o.sets, "configuration override key=value (repeatable); see --keys");
  app.add_option("--lcm-url", o.lcm_url, "LCM provider URL (default: LCM_DEFAULT_URL or LCM's default)")
      ->check(CLI::Validator(gimbalsim::lcm_wire::lcmUrlProblem, "URL"));
  app.add_option("--channel-prefix", o.prefix, "prefix of every channel name, e.g. BENCH2_");
  // The same ticks as firmware_sim --duration: statuses 0 .. round(T / period) - 1.
  app.add_option("--duration", o.duration, "stop after answering the last status of a run of this length [s], as "
                                           "firmware_sim --duration counts it (0 = until SIGINT/SIGTERM)")
      ->check(program::within(0.0, 1e9));
  app.add_option("--idle-exit", o.idle_exit, "wait at most this many wall seconds for the first status, then exit 6 "
                                             "(no peer) (0 = wait forever)")
      ->check(program::zeroOrWithin(0.1, 1e9));  // the loop reads its clock every 0.1 s at least (kPollMs)
  app.add_option("--plant-timeout", o.plant_timeout, "after the first status, this many wall seconds without one "
                                                     "mean the plant has gone: say so, exit 6 (0 = never)")
      ->capture_default_str()->check(program::zeroOrWithin(0.1, 1e9));  // (1e-300 declared a live plant gone)
  app.add_option("--log-csv", o.log_csv, "write one row per status answered: reference, measurement, torque");
  app.add_option("--spin-us", o.spin_us, "busy-poll up to US for the next status before sleeping: a lockstep "
                                         "plant's next status comes within microseconds [us, at most 100000]")
      ->capture_default_str()->check(program::within(0.0, 100000.0));
  app.add_flag("--keys", o.keys, "list every configuration key with type, unit, default, check and meaning, then exit");
  app.add_flag("--markdown", o.markdown, "with --keys: as a Markdown table (the one in docs/controller_keys.md)");
  app.add_flag("--print-config", o.print_config,
               "print the configuration in effect (file + --set) as key=value lines, then exit");
  if (const auto rc = program::parse(app, argc, argv, "pointing_controller")) return *rc;
  if (const std::string why = lcm_wire::defaultLcmUrlProblem(o.lcm_url); !why.empty()) {
    return program::refuse("pointing_controller", why);
  }
  // (pass 119) what a listing mode never reads was taken without a word (--keys --log-csv /proc/x.csv, exit 0;
  // --markdown alone started a controller)
  if (o.markdown && !o.keys) return program::refuse("pointing_controller", "--markdown: only --keys reads it");
  const char* const run_flags[] = {"--lcm-url", "--channel-prefix", "--duration", "--idle-exit", "--plant-timeout",
                                   "--log-csv", "--spin-us"};
  for (const char* f : run_flags) {  // --print-config judges a --duration against the period (run_hil_bench.sh)
    if ((o.keys || (o.print_config && std::string(f) != "--duration")) && app.count(f) > 0) {
      return program::refuse("pointing_controller", std::string(f) + ": " + (o.keys ? "--keys" : "--print-config") +
                                                        " prints and exits; it runs no controller");
    }
  }
  if (o.keys && (o.print_config || !o.config.empty() || !o.sets.empty())) {
    return program::refuse("pointing_controller", "--keys lists the keys of every configuration: a configuration, "
                                                  "--set or --print-config beside it is not read");
  }
  if (o.keys) {
    const std::vector<KeyInfo> all = controllerKeys();
    std::fputs((o.markdown ? keysMarkdown(all) : keysText(all)).c_str(), stdout);
    return program::kOk;
  }
  if (const std::string why = contract::Channels::prefixProblem(o.prefix); !why.empty()) {
    return program::refuse("pointing_controller", "--channel-prefix '" + o.prefix + "': " + why);
  }
  ControllerConfig c;
  try {
    // No file: the built-in defaults (ControllerConfig's), never a path baked in at build time.
    c = o.config.empty() ? loadControllerConfigText("", "the built-in default configuration", o.sets)
                         : loadControllerConfig(o.config, o.sets);
  } catch (const ConfigError& e) {  // the exit-code table's form, as every program's (pass 61)
    return program::refuse("pointing_controller", e);
  }
  // (pass 97) a --set this configuration reads in no run (control.rate_filter_hz without rate_source difference)
  // was taken, --print-config showing it in effect: refused as the studies refuse it (the plant's antenna sensor
  // is the plant's to say: taken as present)
  if (const std::string why = idleControllerOverride("--set", o.sets, c, true, {}); !why.empty()) {
    return program::refuse("pointing_controller", why);
  }
  // Whole control periods, as firmware_sim counts them: a duration between two is refused, never rounded.
  if (const std::string why = wholeMultipleProblem(o.duration, c.period, "the control period (control.period)");
      o.duration != 0.0 && !why.empty()) {
    return program::refuse("pointing_controller", "--duration: " + why);
  }
  if (o.print_config) {
    for (const std::string& kv : configValues(c)) std::printf("%s\n", kv.c_str());
    return program::kOk;
  }
  // --log-csv: a temporary file renamed over the target at exit (also after
  // SIGINT/SIGTERM), never through a link, never over the configuration.
  std::optional<io::OutputFile> log_out;
  if (!o.log_csv.empty()) {
    try {
      log_out.emplace(o.log_csv, o.config.empty() ? std::vector<std::string>{} : std::vector<std::string>{o.config});
    } catch (const io::OutputError& e) {
      const std::string what = std::string("--log-csv: ") + e.what();
      return e.unwritable() ? program::unwritable("pointing_controller", what) : program::refuse("pointing_controller", what);
    }
    log_out->write(StatusHandler::header());
  }
  lcm_wire::UdpmSender tx;
  if (std::string why; !tx.open(o.lcm_url, &why)) {
    std::fprintf(stderr, "pointing_controller: LCM could not start: %s\n", why.c_str());
    return program::kNetwork;
  }
  const contract::Channels ch = contract::Channels::withPrefix(o.prefix);
  StatusHandler h(c, tx, ch, log_out ? &*log_out : nullptr);
  lcm_wire::ReassemblyLimits lim;  // statuses, attitudes and antenna messages are < 1 kB
  lim.max_message_bytes = 4096;
  lcm_wire::UdpmReceiver rx(lim, lcm_wire::ChannelFilter({ch.status, ch.attitude, ch.antenna}));
  if (std::string why; !rx.open(o.lcm_url, 4 << 20, &why)) {
    std::fprintf(stderr, "pointing_controller: cannot receive: %s\n", why.c_str());
    return program::kNetwork;
  }
  // sigaction without SA_RESTART: the wait returns at once on SIGINT/SIGTERM.
  io::installStopHandlers();
  std::fprintf(stderr, "pointing_controller: %s -> %s, period %g s, profile: slew to (%g, %g) rad at %g s for %g s, "
               "hold %g s, track from %g s\n", ch.status.c_str(), ch.command.c_str(), c.period,
               c.profile.slew_target(0), c.profile.slew_target(1), c.profile.slew_start, c.profile.slew_time,
               c.profile.hold_time, c.profile.trackStart());
  int code = program::kOk;
  constexpr int kPollMs = 100;
  constexpr int kDrainMax = 256;  // datagrams per round: a flood cannot hold the loop
  // The last status of a run of --duration T is seq round(T / period) - 1 (firmware_sim's count).
  const std::int64_t last_seq = o.duration > 0.0 ? std::llround(o.duration / c.period) - 1 : -1;
  std::int64_t last_answer_ns = lcm_wire::monotonicNs();
  const std::int64_t spin_ns = std::llround(o.spin_us * 1e3);
  while (!io::stopRequested()) {
    const long long before = h.answered();
    // The wait and the read in one system call (a lockstep turn's cost is its count of calls).
    if (rx.waitDrain(kPollMs, spin_ns, [&h](const lcm_wire::Message& m, std::int64_t) {
          h.onMessage(m, lcm_wire::monotonicNs());
        }, kDrainMax) < 0) {
      std::fprintf(stderr, "pointing_controller: receive failed (socket error)\n");
      code = program::kNetwork;
      break;
    }
    const std::int64_t now = lcm_wire::monotonicNs();
    if (h.answered() > before) last_answer_ns = now;
    if (log_out && !log_out->ok()) {
      std::fprintf(stderr, "pointing_controller: --log-csv %s; stopping\n", log_out->error().c_str());
      code = program::kOutput;
      break;
    }
    if (h.runEnded(last_seq)) break;
    const double idle = static_cast<double>(now - last_answer_ns) * 1e-9;  // [s] wall time since the last status
    if (h.answered() == 0 && o.idle_exit > 0.0 && idle >= o.idle_exit) {
      std::fprintf(stderr, "pointing_controller: no status for %g s, exiting: no plant on %s\n", o.idle_exit,
                   ch.status.c_str());
      code = program::kNoPeer;
      break;
    }
    if (h.answered() > 0 && o.plant_timeout > 0.0 && idle >= o.plant_timeout) {
      if (h.notFinite() > 0) {  // a lockstep plant waits for the answer this controller could not send
        std::fprintf(stderr, "pointing_controller: no status for %g s after status %lld at t = %.3f s, with %lld "
                     "answers not sent (a torque NaN or Inf): a lockstep plant waits for them\n", o.plant_timeout,
                     static_cast<long long>(h.lastSeq()), h.lastTime(), h.notFinite());
        code = program::kStopped;
        break;
      }
      // A plant that stopped (FAULT_PLANT_FAULT) and then ended ended the run as firmware_sim's own exit says
      // (3): its going is the end of a stopped run, not a missing peer.
      const bool stopped = !std::isnan(h.plantStoppedTime());
      std::fprintf(stderr, "pointing_controller: the plant has gone: no status for %g s (--plant-timeout) after "
                   "status %lld at t = %.3f s%s\n", o.plant_timeout, static_cast<long long>(h.lastSeq()), h.lastTime(),
                   stopped ? ", after it had stopped (FAULT_PLANT_FAULT)"
                           : last_seq >= 0 ? ", before the end of --duration" : "");
      code = stopped ? program::kStopped : program::kNoPeer;
      break;
    }
  }
  // A controller none of whose commands the plant took did not control it: not a success.
  // The same when the plant went away after refusing every answer (a lockstep
  // plant ends so): the refusal is the story, not the missing peer.
  const bool plant_went = code == program::kNoPeer && h.answered() > 0;
  // (pass 103) and one that took fewer than it takes to judge, the rest refused (a 10-tick run, t = 0's taken)
  const long long refused = h.answered() - h.accepted() - 1;  // the last answer's fate shows in no status
  if ((code == program::kOk || plant_went) && h.answered() >= kStatusesToJudge &&
      (!h.acceptedAny() || (h.accepted() < kStatusesToJudge && refused >= kStatusesToJudge))) {
    std::fprintf(stderr, "pointing_controller: the plant accepted %s of the commands answering %lld statuses (%lld "
                 "not sent: a torque NaN or Inf); the plant's summary says why it refused or lost the rest\n",
                 h.acceptedAny() ? ("only " + std::to_string(h.accepted())).c_str() : "none", h.answered(),
                 h.notFinite());
    code = program::kStopped;
  }
  // A lockstep plant ends the run after kRejectedInARow answers it rejected, or sooner when it waited
  // --lockstep-timeout-ms for each of them: the refusal is the story, not the missing peer (pass 71, 73: exit 6).
  if (plant_went && h.rejectedInARow() >= 1) {
    std::fprintf(stderr, "pointing_controller: the plant rejected our answers to its last %lld statuses and then "
                 "ended the run: the plant's summary says why it refused them\n", h.rejectedInARow());
    code = program::kStopped;
  }
  // A tick answered with no command (NaN or Inf torque) left the plant on its
  // last one: the run did not control it throughout, whatever it accepted.
  if (code == program::kOk && h.notFinite() > 0) {
    std::fprintf(stderr, "pointing_controller: %lld of %lld answers not sent: a torque NaN or Inf (the plant kept "
                 "its last command); check the configuration's ranges\n", h.notFinite(), h.answered());
    code = program::kStopped;
  }
  // A plant that stopped (FAULT_PLANT_FAULT) ended the run there, whatever the statuses after it: the run
  // stopped, as firmware_sim's own exit says (3), never a success.
  if (code == program::kOk && !std::isnan(h.plantStoppedTime())) code = program::kStopped;
  if (log_out && h.answered() == 0) {
    // No status, no run: the log would hold its header alone, over the previous run's (pass 82).
    log_out.reset();
    std::fprintf(stderr, "pointing_controller: --log-csv: nothing written (no status answered): %s is as it was\n",
                 o.log_csv.c_str());
  } else if (log_out && !log_out->commit()) {
    std::fprintf(stderr, "pointing_controller: --log-csv: %s\n", log_out->error().c_str());
    if (code == program::kOk) code = program::kOutput;
  }
  // A run that ended before the track has no tracking figure: n/a with the reason, never 0.
  // No status at all is no run: "run ended at 0 s" would invent an end time.
  std::string no_track_figure =
      h.answered() == 0 ? "no status answered"
                        : pointing::windowNotReached(pointing::profileWindow(c.profile, Segment::Track),
                                                     pointing::WindowNeed::Part,
                                                     std::isnan(h.plantStoppedTime()) ? h.lastTime()
                                                                                      : h.lastGoodTime());
  if (no_track_figure.empty() && std::isnan(h.maxTrackError())) {
    no_track_figure = "no reading accepted while tracking: " + std::to_string(h.trackStatuses()) +
                      " status(es) there, each with a NaN or Inf";
  }
  const std::string track_error = pointing::figureText(h.maxTrackError(), no_track_figure, "%.3e rad");
  char last_t[48] = "n/a: none answered";  // a time of 0 for no status is a figure over nothing
  if (h.answered() > 0) std::snprintf(last_t, sizeof last_t, "%.3f s", h.lastTime());
  std::fprintf(stderr, "pointing_controller: answered %lld statuses (last t = %s), %lld with the command at its "
               "own torque limit (azimuth/elevation.torque_limit), %lld undecodable, %lld publish "
               "errors, %lld plant restarts, max |joint error| while tracking %s (encoder), status faults seen 0x%x, "
               "%lld statuses without their attitude (gyro held), %lld in a star tracker outage, %lld readings "
               "rejected (NaN or Inf: the last command held), %lld answers not sent (a torque NaN or Inf)\n",
               h.answered(), last_t, h.controllerLimited(), h.undecodable(), h.publishErrors(), h.plantRestarts(), track_error.c_str(),
               h.faultsSeen(), h.unpaired(), h.outageStatuses(), h.rejectedReadings(), h.notFinite());
  if (!std::isnan(h.plantStoppedTime())) {  // the statuses ran on; the plant did not
    char good[48] = "its first status";  // a plant faulted from its first status has no good state to name
    if (!std::isnan(h.lastGoodTime())) std::snprintf(good, sizeof good, "t = %.6g s", h.lastGoodTime());
    // The statuses carry their tick's time: a step that failed inside the period froze the plant up to one
    // period after its last good status (firmware_sim and the truth CSV name that state's own time).
    std::fprintf(stderr, "pointing_controller: the plant stopped after %s, its last good status (FAULT_PLANT_FAULT "
                 "from the status at t = %.6g s): the statuses after it are in no figure above (the tracking "
                 "error, the torque-limit count)\n", good, h.plantStoppedTime());
  }
  const MonitorState& mon = h.monitor();
  std::fprintf(stderr, "pointing_controller: fault monitor: %lld stale statuses (%lld with safe torque), %lld statuses "
               "missing, encoder suspect %lld times on azimuth, %lld on elevation\n",
               mon.stale_statuses, mon.safe_statuses, mon.missing_statuses, mon.suspect_onsets[0], mon.suspect_onsets[1]);
  std::fprintf(stderr, "pointing_controller: receive: %s; %lld from another source than the plant (ignored), %lld "
               "rebinds to another plant source; peak memory (VmHWM) %ld kB\n", rx.summary().c_str(), h.foreign(),
               h.rebinds(), lcm_wire::peakRssKb());
  // Stopped by SIGINT/SIGTERM, --log-csv whole: 128 + the signal.
  return code == program::kOk && io::stopRequested() ? io::stopExitCode() : code;
}

}  // namespace
}  // namespace gimbalsim::controllers

int main(int argc, char** argv) {
  return gimbalsim::program::guardedMain("pointing_controller", [&] { return gimbalsim::controllers::run(argc, argv); });
}
