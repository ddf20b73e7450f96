// Lockstep mode: one thread; tick k+1 runs once the command answering
// status k has arrived (or a timeout), utime is simulated time, and runs are
// bit-for-bit repeatable. docs/bench.md "Real time and lockstep".
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "app.hpp"
#include "gimbalsim/contract/channels.hpp"
#include "gimbalsim/contract/messages.hpp"
#include "gimbalsim/dynamics/simulate.hpp"
#include "lcm_bridge.hpp"
#include "realtime.hpp"
#include "summary.hpp"
#include "tick_log.hpp"
#include "truth_csv.hpp"

namespace gimbalsim::firmware {
namespace {

constexpr std::int64_t kRepublishNs = 200000000;  ///< status 0 again every 200 ms until answered

/// Lockstep's command intake: one thread, so the bridge hands each decoded
/// command straight to the firmware (no ring), and notes when an accepted
/// one answers the awaited status (a rejected one, e.g. a spoof or a NaN
/// torque, never releases the gate).
template <class V>
class FirmwareSink final : public CommandSink {
 public:
  explicit FirmwareSink(Firmware<V>& fw) : fw_(fw) {}
  void await(std::int64_t status_seq) noexcept {
    awaited_ = status_seq;
    answered_ = false;
  }
  bool answered() const noexcept { return answered_; }
  bool take(const Inbound& m) noexcept override {
    if (deliver(fw_, m) && m.cmd.status_seq == awaited_) answered_ = true;
    return true;
  }

 private:
  Firmware<V>& fw_;
  std::int64_t awaited_ = -2;
  bool answered_ = false;
};

/// Waits for the command answering status k, the one published this tick
/// (for status 0: re-publishes it until a controller answers, up to the
/// start timeout). True when answered.
template <class V>
bool awaitAnswer(Run& r, FirmwareSink<V>& sink, const Firmware<V>& fw, std::int64_t k, std::int64_t spin_ns) {
  const Options& o = r.setup.o;
  const bool first = k == 0;
  const std::int64_t wait_ns = first ? std::llround(o.start_timeout_s * 1e9) : std::llround(o.lockstep_timeout_ms * 1e6);
  const std::int64_t deadline = nowNs() + wait_ns;
  std::int64_t republish = nowNs() + kRepublishNs;
  sink.await(k);
  while (!sink.answered() && !g_stop.load()) {
    const std::int64_t now = nowNs();
    if (now >= deadline) break;
    if (first && now >= republish) {
      r.ports.bridge.publish(fw.attitude());
      r.ports.bridge.publish(fw.status());
      r.ports.bridge.flush();
      republish = now + kRepublishNs;
    }
    const std::int64_t until = first ? std::min(deadline, republish) : deadline;
    const int ms = static_cast<int>(std::max<std::int64_t>(1, (until - now + 999999) / 1000000));
    if (!r.ports.bridge.receive(ms, spin_ns) && !g_stop.load()) {  // (a signal interrupts the wait: not an error)
      std::fprintf(stderr, "firmware_sim: receive failed (socket error)\n");
      g_stop.store(true);
    }
  }
  return sink.answered();
}

/// The ending without an answer: the summary and the exit code. A
/// controller that did answer, but only with commands the plant rejected,
/// is there: the run stopped (kExitPlantFault's code, 3), not "no peer".
template <class V>
int endWithoutAnswer(Run& r, const BenchTick<V>& tick, std::int64_t wall0, bool rejected_answers) {
  r.report.wall_seconds = static_cast<double>(nowNs() - wall0) * 1e-9;
  r.report.pointing = tick.pointing();
  printExitSummary(r, outcomeOf(tick.firmware()));
  return rejected_answers ? kExitPlantFault : kExitNoController;
}

/// Rejections the controller's own commands earn (not a stranger's, not garbage bytes): what ends a run after
/// contract::kRejectedInARow answers in a row, as the in-process closed loop ends it.
std::int64_t ownRejections(const Counters& c) noexcept {
  return c.rejected - c.by_reason[static_cast<int>(Rejection::WrongSource)] -
         c.by_reason[static_cast<int>(Rejection::Undecodable)];
}

/// The commands rejected since `before` (cumulative counters), with the most frequent reason; "" if none came.
std::string rejectedSince(const Counters& before, const Counters& now) {
  const std::int64_t n = now.rejected - before.rejected;
  if (n <= 0) return "";
  return std::to_string(n) + " command(s) arrived and the plant rejected every one (" +
         describe(commonestRejection(before, now)) + "): the controller answers, but nothing it sends can act";
}

template <class V>
int run(Run& r) {
  const Options& o = r.setup.o;
  const double period = r.setup.c.control_period;
  BenchTick<V> tick(r.setup.plant, r.setup.c, r.setup.faults, r.setup.profile);
  Firmware<V>& fw = tick.firmware();
  FirmwareSink<V> sink(fw);
  const SinkBinding bound(r.ports.bridge, &sink);
  const std::int64_t total = totalTicks(o, r.setup.c);
  const std::int64_t wall0 = nowNs();
  std::int32_t extra = 0;
  const std::int64_t spin_ns = std::llround(o.spin_us * 1e3);  // --spin-us: busy-poll for the answer
  long long timeouts_in_a_row = 0;  // lockstep timeouts since the last answer
  long long rejected_in_a_row = 0;   // statuses in a row answered only by commands the plant rejected
  Counters unanswered_from;          // the firmware's counters when the current run of timeouts began
  Counters rejected_from;            // ... when the current run of rejected answers began
  std::int64_t next_stats = wall0 + std::llround(o.stats_period * 1e9);
  warmUp(fw);
  std::int64_t cpu_last_end = nowNs(CLOCK_THREAD_CPUTIME_ID);  // [ns] thread CPU at the end of the last tick's work
  // k = total is the run's end: the plant's state at T, sampled as every
  // tick (as the in-process closed loop does) but never stepped; only its
  // truth goes out, so the truth CSV holds t = 0 .. T.
  for (std::int64_t k = 0; (total < 0 || k <= total) && !g_stop.load(); ++k) {
    const bool end = k == total;
    TickTimes tt{};
    tt.wall_start = nowNs();
    // The thread's CPU span starts where the last tick's ended: it holds the command's intake (the wait's
    // system calls, not the time asleep) and costs no clock read between the command and the status.
    tt.cpu_start = cpu_last_end;
    // Lockstep's clock: utime is simulated time.
    const std::int64_t utime = std::llround(static_cast<double>(k) * period * 1e6);
    const TickMessages m = tick.sample(k, utime, k % o.truth_every == 0, extra);
    extra = 0;
    if (!end) r.ports.bridge.publish(*m.attitude);  // before the status, so a controller has it when the status comes
    if (m.antenna) r.ports.bridge.publish(*m.antenna);
    if (m.status && !end) r.ports.bridge.publish(*m.status);
    r.ports.bridge.flush();  // what the controller answers, in one system call
    if (m.truth) {
      // Sent apart, after: in the status's call it delayed the answer by its own send (docs/bench.md "Lockstep speed")
      r.ports.bridge.publish(*m.truth);
      r.ports.bridge.flush();
      if (!r.ports.csv.write(*m.truth, m.antenna)) g_stop.store(true);  // a failed write stops the run (exit 4)
    }
    if (end) break;
    tt.cpu_step = nowNs(CLOCK_THREAD_CPUTIME_ID);
    tick.advance();
    tt.cpu_end = nowNs(CLOCK_THREAD_CPUTIME_ID);
    cpu_last_end = tt.cpu_end;
    tt.wall_end = nowNs();
    account(r, fw, k, tt);
    if (nowNs() >= next_stats) {
      r.ports.bridge.publishStats(utime, r.report.stats, false, true);
      r.ports.bridge.flush();
      next_stats = nowNs() + std::llround(o.stats_period * 1e9);
    }
    // A status dropped or still held by the fault schedule: nothing to answer, the next tick follows.
    if (!m.status) continue;

    if (timeouts_in_a_row == 0) unanswered_from = fw.counters();
    const std::int64_t foreign_before = fw.counters().by_reason[static_cast<int>(Rejection::WrongSource)];
    const Counters before_answer = fw.counters();
    const bool answered = awaitAnswer(r, sink, fw, fw.status().seq, spin_ns);
    // Answered only by commands the plant rejected, kRejectedInARow statuses in a row: the controller controls
    // nothing; the run ends there, exit 3, as the in-process loop ends it (pass 71: it ran on and exited 0).
    if (answered || ownRejections(fw.counters()) == ownRejections(before_answer)) {
      rejected_in_a_row = 0;
    } else if (++rejected_in_a_row == 1) {
      rejected_from = before_answer;
    }
    if (rejected_in_a_row >= contract::kRejectedInARow && !g_stop.load()) {
      std::fprintf(stderr, "firmware_sim: lockstep: the plant accepted none of the controller's last %lld commands "
                   "(%s): stopping at t = %.3f s, as the in-process closed loop stops\n", rejected_in_a_row,
                   describe(commonestRejection(rejected_from, fw.counters())), static_cast<double>(fw.ticks()) * period);
      return endWithoutAnswer(r, tick, wall0, true);
    }
    if (!answered && !g_stop.load()) {
      if (fw.status().seq == 0) {
        const std::string rejected = rejectedSince(unanswered_from, fw.counters());  // ending: may allocate
        if (rejected.empty()) {
          std::fprintf(stderr,
                       "firmware_sim: lockstep: no command answering status 0 arrived within --start-timeout %g s "
                       "on channel %s; is the controller running with the same --lcm-url and --channel-prefix?\n",
                       o.start_timeout_s, (o.prefix + Channels::kCommand).c_str());
        } else {
          std::fprintf(stderr,
                       "firmware_sim: lockstep: no valid command answered status 0 within --start-timeout %g s: %s\n",
                       o.start_timeout_s, rejected.c_str());
        }
        // No peer: no run, no output (pass 82). A controller whose every answer was rejected took part: its
        // run stopped (exit 3) and its outputs hold what ran (pass 86: they were left as the previous run's).
        r.report.unanswered_start = rejected.empty();
        return endWithoutAnswer(r, tick, wall0, !rejected.empty());
      }
      extra = kLockstepTimeout;
      ++r.report.lockstep_timeouts;
      // The bound controller let --lockstep-timeout-ms pass while another source answered this status (a
      // restarted controller, or one that a stranger's single command had locked out): the binding lapses
      // here, as a watchdog trip ends it; counting the watchdog's ticks at one timeout each would outlast
      // --start-timeout, and the plant stopped with the answering controller never accepted.
      if (fw.counters().by_reason[static_cast<int>(Rejection::WrongSource)] > foreign_before) {
        fw.releaseBinding();
        ++r.report.lockstep_rebinds;
      }
      // A controller that has gone would cost --lockstep-timeout-ms per tick for ever: after
      // --start-timeout without any answer, say so and end (the no-peer code).
      if (++timeouts_in_a_row * o.lockstep_timeout_ms * 1e-3 >= o.start_timeout_s) {
        const std::string rejected = rejectedSince(unanswered_from, fw.counters());
        std::fprintf(stderr,
                     "firmware_sim: lockstep: no %scommand answered the last %lld statuses (%g s of "
                     "--lockstep-timeout-ms %g): %s; stopping at t = %.3f s\n",
                     rejected.empty() ? "" : "valid ", timeouts_in_a_row,
                     static_cast<double>(timeouts_in_a_row) * o.lockstep_timeout_ms * 1e-3, o.lockstep_timeout_ms,
                     rejected.empty() ? "the controller has gone" : rejected.c_str(),
                     static_cast<double>(fw.ticks()) * period);
        return endWithoutAnswer(r, tick, wall0, !rejected.empty());
      }
    } else {
      timeouts_in_a_row = 0;
    }
  }
  r.report.wall_seconds = static_cast<double>(nowNs() - wall0) * 1e-9;
  r.report.pointing = tick.pointing();
  r.ports.bridge.publishStats(std::llround(static_cast<double>(fw.ticks()) * period * 1e6), r.report.stats, false, true);
  r.ports.bridge.flush();
  return finish(r, outcomeOf(fw));
}

}  // namespace

int runLockstep(Run& r) {
  return dispatchVariant(r.setup.plant.scene.model, [&](auto tag) { return run<decltype(tag)>(r); });
}

}  // namespace gimbalsim::firmware
