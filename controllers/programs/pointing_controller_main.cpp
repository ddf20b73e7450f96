// pointing_controller: the controller library on the other side of LCM. It
// subscribes to the gimbal status and answers EVERY status at once with one
// torque command whose status_seq is that status's seq (this is what lets
// firmware_sim --lockstep advance). Profile time is seq * control.period, the
// plant's simulated time, so the controller may join a running bench. The
// attitude message (GIMBAL_ATTITUDE, published just before the status of the
// same tick) is kept; the status uses it when the seqs match, else the gyro
// sample counts as missing (answerStatus), exactly as the in-process loop.
// The status handler decodes into a stack message (fixed-size arrays: no
// allocation), runs update() and encodes into a preallocated buffer for LCM's
// raw publish (the typed publish allocates on every call). Receiving is our
// bounded UDP receiver (lcm_wire/udpm_receiver.hpp), not LCM's receive
// thread, which LCM 1.3.1 lets crash on one malformed fragment. Statuses are
// taken from one plant (the source of the first, until it has been silent
// for kRebindNs), so a spoofed status cannot reset or steer the controller.
// Flags: docs/usage.md; exit codes: the project's table (docs/usage.md "Exit codes", mirrored in program.hpp).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <string>
#include <optional>
#include <vector>

#include "gimbalsim/io/csv_format.hpp"
#include "gimbalsim/io/output_file.hpp"
#include "gimbalsim/lcm_wire/peak_memory.hpp"
#include "gimbalsim/lcm_wire/udpm_receiver.hpp"

#include "gimbalsim/program/program.hpp"
#include "gimbalsim/contract/channels.hpp"
#include "gimbalsim/controllers/answer.hpp"
#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/input/key_registry.hpp"
#include "gimbalsim/pointing/profile_windows.hpp"
#include "gimbalsim/gimbal_attitude_t.hpp"
#include "gimbalsim/gimbal_command_t.hpp"
#include "gimbalsim/gimbal_status_t.hpp"

namespace gimbalsim::controllers {
namespace {

/// Statuses after which a plant that accepted none of the commands has had
/// its chance: the status after a command reports it (lockstep and real time).
constexpr long long kStatusesToJudge = 3;

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

/// Answers statuses; everything it needs is allocated before the first one.
class StatusHandler {
 public:
  StatusHandler(const ControllerConfig& c, lcm::LCM& lcm, const contract::Channels& ch, std::FILE* csv)
      : c_(c), lcm_(lcm), ch_(ch), csv_(csv) {}

  /// One received message; the channel says which handler. now_ns: CLOCK_MONOTONIC.
  void onMessage(const lcm_wire::Message& m, std::int64_t now_ns) {
    if (!fromPlant(m.source, now_ns)) return;
    const int size = static_cast<int>(m.size);  // bounded by the receiver's limit
    if (m.channel == ch_.status) onStatus(m.data, size);
    else if (m.channel == ch_.attitude) onAttitude(m.data, size);
  }

  void onAttitude(const std::uint8_t* data, int size) {
    gimbal_attitude_t m{};
    if (m.decode(data, 0, size) != size) {
      ++undecodable_;
      return;
    }
    contract::copyFields<contract::AttitudeFields>(attitude_, m);
    noteAttitude(state_, attitude_);  // a late status finds the attitude of its tick (fault_monitor.hpp)
  }

  void onStatus(const std::uint8_t* data, int size) {
    gimbal_status_t st{};
    if (st.decode(data, 0, size) != size) {
      ++undecodable_;  // garbage, another type or trailing bytes on the status channel
      return;
    }
    if (st.seq < last_status_seq_) {  // the plant restarted: start the controller afresh
      state_ = ControllerState{};
      ++restarts_;
    }
    last_status_seq_ = st.seq;
    // The same answer as the in-process loop's (PointingController): seq from
    // this process's own counter, strictly increasing.
    contract::Status status;
    contract::copyFields<contract::StatusFields>(status, st);
    if (attitude_.seq != status.seq) ++unpaired_;
    const Answer a = answerStatus(c_, state_, status, attitude_, next_seq_);
    const Measurement& meas = a.meas;
    const ControlOutput& out = a.out;
    if (std::isfinite(a.cmd.torque[0]) && std::isfinite(a.cmd.torque[1])) {
      gimbal_command_t cmd{};
      contract::copyFields<contract::CommandFields>(cmd, a.cmd);
      const int n = cmd.encode(buf_.data(), 0, static_cast<int>(buf_.size()));
      if (n < 0 || lcm_.publish(ch_.command, buf_.data(), static_cast<unsigned>(n)) != 0) ++publish_errors_;
      if (first_sent_seq_ < 0) first_sent_seq_ = a.cmd.seq;
    } else {
      ++not_finite_;  // never sent: NaN or Inf is no command (the plant would refuse it)
    }
    if (first_sent_seq_ >= 0 && st.last_command_seq >= first_sent_seq_) accepted_any_ = true;
    // Bookkeeping after the answer is on its way.
    ++answered_;
    last_t_ = meas.t;
    faults_seen_ |= st.faults;
    if (out.star_outage) ++outage_statuses_;
    if (out.saturated[0] || out.saturated[1]) ++controller_limited_;
    if (out.ref.segment == Segment::Track) max_track_error_ = std::max(max_track_error_, out.error.cwiseAbs().maxCoeff());
    if (csv_) log(st, meas, out, a.flags);
  }

  static void header(std::FILE* f) {
    // The cells as name[unit], written in the project's CSV names (io::csvNameOf: t_s, tau_az_Nm).
    static constexpr const char* kCells =
        "t[s],seq[-],segment[-],ref_az[rad],ref_el[rad],ref_daz[rad/s],ref_del[rad/s],ref_ddaz[rad/s^2],"
        "ref_ddel[rad/s^2],meas_az[rad],meas_el[rad],rate_az[rad/s],rate_el[rad/s],err_az[rad],"
        "err_el[rad],tau_az[N m],tau_el[N m],tau_unsat_az[N m],tau_unsat_el[N m],faults[-],prof_az[rad],"
        "prof_el[rad],est_qw[-],est_qx[-],est_qy[-],est_qz[-],est_wx[rad/s],est_wy[rad/s],est_wz[rad/s],"
        "star_outage[-],attitude_paired[-],stale[-],safe[-],suspect_az[-],suspect_el[-]";
    std::string h, cell;
    for (const char* c = kCells;; ++c) {
      if (*c == ',' || *c == '\0') {
        (h.empty() ? h : h += ',') += io::csvNameOf(cell);
        cell.clear();
        if (*c == '\0') break;
      } else {
        cell += *c;
      }
    }
    std::fputs((h + "\n").c_str(), f);
  }

  /// The plant is the source of the first message; another source is taken
  /// only after the bound one has been silent for kRebindNs (a restarted plant).
  bool fromPlant(lcm_wire::Source src, std::int64_t now_ns) {
    if (bound_ && !(src == plant_) && now_ns - plant_heard_ns_ < kRebindNs) {
      ++foreign_;
      return false;
    }
    bound_ = true;
    plant_ = src;
    plant_heard_ns_ = now_ns;
    return true;
  }

  long long answered() const { return answered_; }
  /// Statuses answered with the command held at this controller's own limit (azimuth/elevation.torque_limit), either axis.
  long long controllerLimited() const { return controller_limited_; }
  std::int64_t lastSeq() const { return last_status_seq_; }
  long long foreign() const { return foreign_; }
  long long plantRestarts() const { return restarts_; }
  long long undecodable() const { return undecodable_; }
  long long publishErrors() const { return publish_errors_; }
  long long notFinite() const { return not_finite_; }
  /// Whether the plant has reported accepting one of this controller's commands.
  bool acceptedAny() const { return accepted_any_; }
  double lastTime() const { return last_t_; }
  int faultsSeen() const { return faults_seen_; }
  double maxTrackError() const { return max_track_error_; }
  long long unpaired() const { return unpaired_; }
  long long outageStatuses() const { return outage_statuses_; }
  const MonitorState& monitor() const { return state_.monitor; }
  long long rejectedReadings() const { return state_.rejected_readings; }

 private:
  void log(const gimbal_status_t& st, const Measurement& m, const ControlOutput& o, const MonitorFlags& f) {
    const ProfileSample& r = o.ref;
    // One line in a fixed buffer (no allocation on the answer path); doubles as io::formatCsvNumber.
    char line[2048];
    int n = io::formatCsvNumber(line, m.t);
    n += std::snprintf(line + n, sizeof line - static_cast<std::size_t>(n), ",%lld,%s", static_cast<long long>(st.seq),
                       describe(r.segment));
    auto num = [&](double x) {
      line[n++] = ',';
      n += io::formatCsvNumber(line + n, x);
    };
    auto flag = [&](int v) { n += std::snprintf(line + n, sizeof line - static_cast<std::size_t>(n), ",%d", v); };
    for (double x : {r.q(0), r.q(1), r.dq(0), r.dq(1), r.ddq(0), r.ddq(1), m.theta(0), m.theta(1), m.dtheta(0),
                     m.dtheta(1), o.error(0), o.error(1), o.tau(0), o.tau(1), o.tau_unsat(0), o.tau_unsat(1)}) {
      num(x);
    }
    flag(st.faults);
    for (double x : {o.profile.q(0), o.profile.q(1), o.q_WB_est.w(), o.q_WB_est.x(), o.q_WB_est.y(),
                     o.q_WB_est.z(), o.omega_B_est(0), o.omega_B_est(1), o.omega_B_est(2)}) {
      num(x);
    }
    for (bool b : {o.star_outage, attitude_.seq == st.seq, f.stale, f.safe, f.encoder_suspect[0],
                   f.encoder_suspect[1]}) {
      flag(b ? 1 : 0);
    }
    line[n++] = '\n';
    std::fwrite(line, 1, static_cast<std::size_t>(n), csv_);
  }

  const ControllerConfig& c_;
  lcm::LCM& lcm_;
  const contract::Channels& ch_;
  std::FILE* csv_;
  ControllerState state_;
  contract::Attitude attitude_{.seq = -1};  ///< the newest attitude message (seq -1: none yet)
  long long unpaired_ = 0;        ///< statuses without the attitude of their tick (gyro rate held)
  long long outage_statuses_ = 0; ///< statuses answered during a star tracker outage
  std::array<std::uint8_t, 256> buf_{};  // a command encodes to well under 256 bytes
  static constexpr std::int64_t kRebindNs = 500000000;  ///< plant silent this long -> another may bind [ns]
  bool bound_ = false;
  lcm_wire::Source plant_;
  std::int64_t plant_heard_ns_ = 0;
  long long foreign_ = 0;  ///< messages from another source than the bound plant (ignored)
  std::int64_t next_seq_ = 0;
  std::int64_t last_status_seq_ = -1;
  long long restarts_ = 0;  ///< statuses whose seq went backwards
  long long answered_ = 0, undecodable_ = 0, publish_errors_ = 0, controller_limited_ = 0;
  long long not_finite_ = 0;            ///< answers not sent: a torque NaN or Inf
  std::int64_t first_sent_seq_ = -1;    ///< seq of the first command sent (-1: none yet)
  bool accepted_any_ = false;
  double last_t_ = 0.0, max_track_error_ = 0.0;
  int faults_seen_ = 0;
};

int run(int argc, char** argv) {
  CLI::App app{"Pointing controller: answers every gimbal status with a torque command over LCM"};
  Options o;
  app.add_option("config", o.config,
                 "controller configuration (YAML): gains, limits, profile (default: the built-in default "
                 "configuration, the values of controllers/config/default.yaml)");
  app.add_option("--set", o.sets, "configuration override key=value (repeatable); see --keys");
  app.add_option("--lcm-url", o.lcm_url, "LCM provider URL (default: LCM_DEFAULT_URL or LCM's default)");
  app.add_option("--channel-prefix", o.prefix, "prefix of every channel name, e.g. BENCH2_");
  // The same ticks as firmware_sim --duration: statuses 0 .. round(T / period) - 1.
  app.add_option("--duration", o.duration, "stop after answering the last status of a run of this length [s], as "
                                           "firmware_sim --duration counts it (0 = until SIGINT/SIGTERM)")
      ->check(CLI::NonNegativeNumber)->check(CLI::Range(0.0, 1e9));
  app.add_option("--idle-exit", o.idle_exit, "wait at most this many wall seconds for the first status, then exit 6 "
                                             "(no peer) (0 = wait forever)")
      ->check(CLI::NonNegativeNumber)->check(CLI::Range(0.0, 1e9));
  app.add_option("--plant-timeout", o.plant_timeout, "after the first status, this many wall seconds without one "
                                                     "mean the plant has gone: say so, exit 6 (0 = never)")
      ->capture_default_str()->check(CLI::NonNegativeNumber)->check(CLI::Range(0.0, 1e9));
  app.add_option("--log-csv", o.log_csv, "write one row per status answered: reference, measurement, torque");
  app.add_option("--spin-us", o.spin_us, "busy-poll up to US for the next status before sleeping: a lockstep "
                                         "plant's next status comes within microseconds [us, at most 100000]")
      ->capture_default_str()->check(CLI::Number)->check(CLI::Range(0.0, 100000.0));
  app.add_flag("--keys", o.keys, "list every configuration key with type, unit, default, check and meaning, then exit");
  app.add_flag("--markdown", o.markdown, "with --keys: as a Markdown table (the one in docs/controller_keys.md)");
  app.add_flag("--print-config", o.print_config,
               "print the configuration in effect (file + --set) as key=value lines, then exit");
  if (const auto rc = program::parse(app, argc, argv, "pointing_controller")) return *rc;
  if (o.keys) {
    const std::vector<KeyInfo> all = controllerKeys();
    std::fputs((o.markdown ? keysMarkdown(all) : keysText(all)).c_str(), stdout);
    return program::kOk;
  }
  if (!contract::Channels::validPrefix(o.prefix)) {
    return program::refuse("pointing_controller",
                           "--channel-prefix '" + o.prefix + "': only A-Z, 0-9 and '_' allowed");
  }
  ControllerConfig c;
  try {
    // No file: the built-in defaults (ControllerConfig's), never a path baked in at build time.
    c = o.config.empty() ? loadControllerConfigText("", "the built-in default configuration", o.sets)
                         : loadControllerConfig(o.config, o.sets);
  } catch (const ConfigError& e) {
    std::fprintf(stderr, "pointing_controller: configuration refused:\n%s\n", e.what());
    return program::kRefused;
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
  std::FILE* csv = nullptr;
  if (!o.log_csv.empty()) {
    try {
      log_out.emplace(o.log_csv, o.config.empty() ? std::vector<std::string>{} : std::vector<std::string>{o.config});
    } catch (const io::OutputError& e) {
      std::fprintf(stderr, "pointing_controller: --log-csv: %s\n", e.what());
      return program::kRefused;
    }
    csv = log_out->stream();
    StatusHandler::header(csv);
  }
  lcm::LCM lcm(o.lcm_url);
  if (!lcm.good()) {
    std::fprintf(stderr, "pointing_controller: LCM could not start (url '%s'); in a fresh network namespace add a "
                 "multicast route: ip link set lo up && ip route add 224.0.0.0/4 dev lo\n", o.lcm_url.c_str());
    return program::kNetwork;
  }
  const contract::Channels ch = contract::Channels::withPrefix(o.prefix);
  StatusHandler h(c, lcm, ch, csv);
  lcm_wire::ReassemblyLimits lim;  // statuses and attitudes are < 1 kB
  lim.max_message_bytes = 4096;
  lcm_wire::UdpmReceiver rx(lim, lcm_wire::ChannelFilter({ch.status, ch.attitude}));
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
    if (rx.wait(kPollMs, spin_ns) < 0) {
      std::fprintf(stderr, "pointing_controller: receive failed (socket error)\n");
      code = program::kNetwork;
      break;
    }
    const long long before = h.answered();
    rx.drain([&h](const lcm_wire::Message& m, std::int64_t) { h.onMessage(m, lcm_wire::monotonicNs()); }, kDrainMax);
    const std::int64_t now = lcm_wire::monotonicNs();
    if (h.answered() > before) last_answer_ns = now;
    if (log_out && !log_out->ok()) {
      std::fprintf(stderr, "pointing_controller: --log-csv %s: %s; stopping\n", o.log_csv.c_str(),
                   log_out->error().empty() ? "write failed" : log_out->error().c_str());
      code = program::kOutput;
      break;
    }
    if (last_seq >= 0 && h.answered() > 0 && h.lastSeq() >= last_seq) break;
    const double idle = static_cast<double>(now - last_answer_ns) * 1e-9;  // [s] wall time since the last status
    if (h.answered() == 0 && o.idle_exit > 0.0 && idle >= o.idle_exit) {
      std::fprintf(stderr, "pointing_controller: no status for %g s, exiting: no plant on %s\n", o.idle_exit,
                   ch.status.c_str());
      code = program::kNoPeer;
      break;
    }
    if (h.answered() > 0 && o.plant_timeout > 0.0 && idle >= o.plant_timeout) {
      std::fprintf(stderr, "pointing_controller: the plant has gone: no status for %g s (--plant-timeout) after "
                   "status %lld at t = %.3f s%s\n", o.plant_timeout, static_cast<long long>(h.lastSeq()), h.lastTime(),
                   last_seq >= 0 ? ", before the end of --duration" : "");
      code = program::kNoPeer;
      break;
    }
  }
  // A controller none of whose commands the plant took did not control it: not a success.
  if (code == program::kOk && h.answered() >= kStatusesToJudge && !h.acceptedAny()) {
    std::fprintf(stderr, "pointing_controller: the plant accepted none of the commands answering %lld statuses (%lld "
                 "not sent: a torque NaN or Inf); the plant's summary says why it refused or lost the rest\n",
                 h.answered(), h.notFinite());
    code = program::kStopped;
  }
  if (log_out && !log_out->commit()) {
    std::fprintf(stderr, "pointing_controller: --log-csv: %s\n", log_out->error().c_str());
    if (code == program::kOk) code = program::kOutput;
  }
  // A run that ended before the track has no tracking figure: n/a with the reason, never 0.
  const std::string track_error = pointing::figureText(
      h.maxTrackError(),
      pointing::windowNotReached(pointing::profileWindow(c.profile, Segment::Track), pointing::WindowNeed::Part,
                                 h.answered() > 0 ? h.lastTime() : 0.0),
      "%.3e rad");
  std::fprintf(stderr, "pointing_controller: answered %lld statuses (last t = %.3f s), %lld with the command at its "
               "own torque limit (azimuth/elevation.torque_limit), %lld undecodable, %lld publish "
               "errors, %lld plant restarts, max |joint error| while tracking %s (encoder), status faults seen 0x%x, "
               "%lld statuses without their attitude (gyro held), %lld in a star tracker outage, %lld readings "
               "rejected (NaN or Inf: the last command held)\n",
               h.answered(), h.lastTime(), h.controllerLimited(), h.undecodable(), h.publishErrors(), h.plantRestarts(), track_error.c_str(),
               h.faultsSeen(), h.unpaired(), h.outageStatuses(), h.rejectedReadings());
  const MonitorState& mon = h.monitor();
  std::fprintf(stderr, "pointing_controller: fault monitor: %lld stale statuses (%lld with safe torque), %lld statuses "
               "missing, encoder suspect %lld times on azimuth, %lld on elevation\n",
               mon.stale_statuses, mon.safe_statuses, mon.missing_statuses, mon.suspect_onsets[0], mon.suspect_onsets[1]);
  std::fprintf(stderr, "pointing_controller: receive: %s; %lld from another source than the plant (ignored); peak "
               "memory (VmHWM) %ld kB\n", rx.summary().c_str(), h.foreign(), lcm_wire::peakRssKb());
  // Stopped by SIGINT/SIGTERM, --log-csv whole: 128 + the signal.
  return code == program::kOk && io::stopRequested() ? io::stopExitCode() : code;
}

}  // namespace
}  // namespace gimbalsim::controllers

int main(int argc, char** argv) {
  return gimbalsim::program::guardedMain("pointing_controller", [&] { return gimbalsim::controllers::run(argc, argv); });
}
