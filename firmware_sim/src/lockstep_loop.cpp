// Lockstep mode: one thread; tick k+1 runs once the command answering
// status k has arrived (or a timeout), utime is simulated time, and runs are
// bit-for-bit repeatable. docs/bench.md "Real time and lockstep".
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "app.hpp"
#include "gimbalsim/contract/channels.hpp"
#include "gimbalsim/dynamics/simulate.hpp"
#include "lcm_bridge.hpp"
#include "realtime.hpp"
#include "summary.hpp"
#include "tick_log.hpp"
#include "truth_csv.hpp"

namespace gimbalsim::firmware {
namespace {

constexpr std::int64_t kRepublishNs = 200000000;  ///< status 0 again every 200 ms until answered

/// Waits for the command answering status k, the one published this tick
/// (for status 0: re-publishes it until a controller answers, up to the
/// start timeout). True when answered.
template <class V>
bool awaitAnswer(Run& r, Firmware<V>& fw, std::int64_t k, std::int64_t spin_ns) {
  const bool first = k == 0;
  const std::int64_t wait_ns = first ? std::llround(r.o.start_timeout_s * 1e9) : std::llround(r.o.lockstep_timeout_ms * 1e6);
  const std::int64_t deadline = nowNs() + wait_ns;
  std::int64_t republish = nowNs() + kRepublishNs;
  bool answered = false;
  while (!answered && !g_stop.load()) {
    drainInbound(fw, r.in, k, &answered);
    if (answered) break;
    const std::int64_t now = nowNs();
    if (now >= deadline) break;
    if (first && now >= republish) {
      r.bridge.publish(fw.attitude());
      r.bridge.publish(fw.status());
      republish = now + kRepublishNs;
    }
    const std::int64_t until = first ? std::min(deadline, republish) : deadline;
    const int ms = static_cast<int>(std::max<std::int64_t>(1, (until - now + 999999) / 1000000));
    if (!r.bridge.receive(ms, spin_ns) && !g_stop.load()) {  // (a signal interrupts the wait: not an error)
      std::fprintf(stderr, "firmware_sim: receive failed (socket error)\n");
      g_stop.store(true);
    }
  }
  return answered;
}

template <class V>
int run(Run& r) {
  Firmware<V> fw(r.plant, r.c, r.faults);
  const pointing::TruthObserver observer(r.plant.scene.model, r.profile, fw.initialBoresight());
  const std::int64_t total = totalTicks(r.o, r.c);
  const std::int64_t wall0 = nowNs();
  std::int32_t extra = 0;
  const std::int64_t spin_ns = std::llround(r.o.spin_us * 1e3);  // --spin-us: busy-poll for the answer
  long long timeouts_in_a_row = 0;  // lockstep timeouts since the last answer
  std::int64_t next_stats = wall0 + std::llround(r.o.stats_period * 1e9);
  warmUp(fw);
  for (std::int64_t k = 0; (total < 0 || k < total) && !g_stop.load(); ++k) {
    const std::int64_t t0 = nowNs();
    const std::int64_t cpu0 = nowNs(CLOCK_THREAD_CPUTIME_ID);  // the CPU span inside the wall span
    drainInbound(fw, r.in);
    const std::int64_t utime = std::llround(static_cast<double>(k) * r.c.control_period * 1e6);
    const bool want_truth = k % r.o.truth_every == 0;
    fw.sample(utime, want_truth, extra);
    extra = 0;
    r.bridge.publish(fw.attitude());  // before the status, so a controller has it when the status comes
    if (fw.statusDelivered()) r.bridge.publish(fw.status());
    if (want_truth) {
      const double t = static_cast<double>(k) * r.c.control_period;
      const Truth truth = observedTruth(fw.truth(), observer, t);
      r.pointing.add(truth.pointing_error, r.profile != nullptr && observer.sample(t).segment == pointing::Segment::Track);
      r.bridge.publish(truth);
      if (!r.csv.write(truth)) g_stop.store(true);  // a failed write stops the run (exit 4)
    }
    const std::int64_t cpu_step = nowNs(CLOCK_THREAD_CPUTIME_ID);
    fw.advance();
    const std::int64_t cpu1 = nowNs(CLOCK_THREAD_CPUTIME_ID);
    const std::int64_t t1 = nowNs();
    r.stats.compute.add(static_cast<double>(t1 - t0) * 1e-3);
    r.stats.addComputeCpu(k, static_cast<double>(cpu1 - cpu0) * 1e-3, static_cast<double>(cpu1 - cpu_step) * 1e-3,
                          fw.lastSubsteps());
    r.tick_log.add(tickRecord(fw, cpu1 - cpu_step, cpu1 - cpu0, t1 - t0));
    r.compute_seconds += static_cast<double>(t1 - t0) * 1e-9;
    r.stats.addTick(k + 1, fw.lastSubsteps());
    if (nowNs() >= next_stats) {
      r.bridge.publishStats(utime, r.stats, false, true);
      next_stats = nowNs() + std::llround(r.o.stats_period * 1e9);
    }
    if (total >= 0 && k + 1 >= total) break;  // the last status needs no answer
    // A status dropped or still held by the fault schedule: nothing to answer, the next tick follows.
    if (!fw.statusDelivered()) continue;

    if (!awaitAnswer(r, fw, fw.status().seq, spin_ns) && !g_stop.load()) {
      if (fw.status().seq == 0) {
        std::fprintf(stderr,
                     "firmware_sim: lockstep: no command answering status 0 arrived within --start-timeout %g s "
                     "on channel %s; is the controller running with the same --lcm-url and --channel-prefix?\n",
                     r.o.start_timeout_s, (r.o.prefix + Channels::kCommand).c_str());
        r.wall_seconds = static_cast<double>(nowNs() - wall0) * 1e-9;
        printExitSummary(r, outcomeOf(fw));
        return kExitNoController;
      }
      extra = kLockstepTimeout;
      ++r.lockstep_timeouts;
      // A controller that has gone would cost --lockstep-timeout-ms per tick for ever: after
      // --start-timeout without any answer, say so and end (the no-peer code).
      if (++timeouts_in_a_row * r.o.lockstep_timeout_ms * 1e-3 >= r.o.start_timeout_s) {
        std::fprintf(stderr,
                     "firmware_sim: lockstep: no command answered the last %lld statuses (%g s of --lockstep-timeout-ms "
                     "%g): the controller has gone; stopping at t = %.3f s\n",
                     timeouts_in_a_row, static_cast<double>(timeouts_in_a_row) * r.o.lockstep_timeout_ms * 1e-3,
                     r.o.lockstep_timeout_ms, static_cast<double>(fw.ticks()) * r.c.control_period);
        r.wall_seconds = static_cast<double>(nowNs() - wall0) * 1e-9;
        printExitSummary(r, outcomeOf(fw));
        return kExitNoController;
      }
    } else {
      timeouts_in_a_row = 0;
    }
  }
  r.wall_seconds = static_cast<double>(nowNs() - wall0) * 1e-9;
  r.bridge.publishStats(std::llround(static_cast<double>(fw.ticks()) * r.c.control_period * 1e6), r.stats, false, true);
  return finish(r, outcomeOf(fw));
}

}  // namespace

int runLockstep(Run& r) {
  return dispatchVariant(r.plant.scene.model, [&](auto tag) { return run<decltype(tag)>(r); });
}

}  // namespace gimbalsim::firmware
