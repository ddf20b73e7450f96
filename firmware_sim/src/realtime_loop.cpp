// Real-time mode: a periodic SCHED_FIFO thread runs the firmware core on
// absolute deadlines, and the communication thread (the caller) does all LCM
// work; the two hand data over through lock-free SPSC queues (no mutex, no
// allocation, no network on the loop thread) and an eventfd to wake the
// communication thread. docs/bench.md "Real time and lockstep".
//
// Wall-clock policy: tick k belongs to deadline t0 + k T and simulated time
// k T, always. A tick whose deadline has already passed when it starts (the
// previous one overran) runs at once, without sleeping and without taking
// new commands (the motor drivers hold the last accepted one), so the plant
// catches up with wall-clock time and every period still gets its status
// and truth; such ticks are counted as late, with how late. docs/bench.md
// "Real time (the default)".
#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <thread>

#include "app.hpp"
#include "gimbalsim/dynamics/simulate.hpp"
#include "lcm_bridge.hpp"
#include "realtime.hpp"
#include "summary.hpp"
#include "tick_log.hpp"
#include "truth_csv.hpp"

namespace gimbalsim::firmware {
namespace {

void printWarnings(const std::vector<std::string>& warnings) {
  for (const std::string& w : warnings) std::fprintf(stderr, "firmware_sim: %s\n", w.c_str());
}

void wake(int efd) {
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t w = ::write(efd, &one, sizeof one);
}

template <class V>
int run(Run& r) {
  Firmware<V> fw(r.plant, r.c, r.faults);
  const pointing::TruthObserver observer(r.plant.scene.model, r.profile, fw.initialBoresight());
  SpscRing<Outbound> out(4096);
  const int efd = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (efd < 0) {
    std::fprintf(stderr, "firmware_sim: eventfd failed: %s\n", std::strerror(errno));
    return kExitInternal;
  }
  const std::int64_t total = totalTicks(r.o, r.c);
  const std::int64_t period_ns = std::llround(r.c.control_period * 1e9);
  const std::int64_t spin_ns = std::llround(r.o.spin_us * 1e3);
  const int truth_every = r.o.truth_every;
  std::atomic<bool> loop_done{false};
  std::atomic<bool> setup_done{false};  // publishes r.rt_warnings and r.fifo to this thread

  auto loop = [&] {
    r.rt_warnings = setUpRealtimeThread(r.o.rt_priority, r.o.cpu, 256 * 1024, &r.fifo);
    setup_done.store(true, std::memory_order_release);
    warmUp(fw);
    // Start on a whole period boundary a little ahead, so set-up does not count as lateness.
    std::int64_t next = (nowNs() / period_ns + 2) * period_ns;
    const std::int64_t realtime_offset = nowNs(CLOCK_REALTIME) - nowNs();  // stamps: the deadline on the wall clock
    std::int64_t prev_wake = -1;
    for (std::int64_t k = 0; (total < 0 || k < total) && !g_stop.load(std::memory_order_relaxed); ++k) {
      const std::int64_t start_ns = nowNs();
      const bool late = start_ns > next;  // the previous tick overran this deadline: catch up
      std::int64_t wake_ns = start_ns;
      if (late) {
        r.stats.late.add(static_cast<double>(start_ns - next) * 1e-4);  // [10 us]
        r.stats.late_ticks.fetch_add(1, std::memory_order_relaxed);
      } else {
        wake_ns = sleepUntil(next, spin_ns);
        r.stats.lateness.add(static_cast<double>(wake_ns - next) * 1e-3);
        if (prev_wake >= 0) r.stats.period.add(static_cast<double>(wake_ns - prev_wake) * 1e-3);
        prev_wake = wake_ns;
      }
      // Read after the wake-up and before `end` below: the CPU span lies inside the wall span
      // and, like it, counts the command intake.
      const std::int64_t wake_cpu_ns = nowNs(CLOCK_THREAD_CPUTIME_ID);
      if (!late) drainInbound(fw, r.in);  // catch-up ticks hold the last accepted command
      const std::int64_t utime = (next + realtime_offset) / 1000;
      const bool want_truth = k % truth_every == 0;
      fw.sample(utime, want_truth);
      Outbound ob;
      ob.attitude = fw.attitude();
      ob.has_status = fw.statusDelivered();
      ob.status = fw.status();
      ob.has_truth = want_truth;
      if (want_truth) {
        const double t = static_cast<double>(k) * r.c.control_period;
        ob.truth = observedTruth(fw.truth(), observer, t);
        r.pointing.add(ob.truth.pointing_error,
                       r.profile != nullptr && observer.sample(t).segment == pointing::Segment::Track);
      }
      if (!out.push(ob)) r.stats.dropped_out.fetch_add(1, std::memory_order_relaxed);
      wake(efd);  // the communication thread
      const std::int64_t step_cpu_ns = nowNs(CLOCK_THREAD_CPUTIME_ID);
      fw.advance();

      const std::int64_t end_cpu_ns = nowNs(CLOCK_THREAD_CPUTIME_ID);
      const std::int64_t end = nowNs();
      r.stats.compute.add(static_cast<double>(end - wake_ns) * 1e-3);
      r.stats.addComputeCpu(k, static_cast<double>(end_cpu_ns - wake_cpu_ns) * 1e-3,
                            static_cast<double>(end_cpu_ns - step_cpu_ns) * 1e-3, fw.lastSubsteps());
      r.tick_log.add(tickRecord(fw, end_cpu_ns - step_cpu_ns, end_cpu_ns - wake_cpu_ns, end - wake_ns));
      r.compute_seconds += static_cast<double>(end - wake_ns) * 1e-9;
      r.stats.addTick(k + 1, fw.lastSubsteps());
      next += period_ns;
      if (end > next) r.stats.overruns.fetch_add(1, std::memory_order_relaxed);  // the next tick starts late
    }
    loop_done.store(true);
    wake(efd);
  };

  const std::int64_t wall0 = nowNs();
  std::thread rt(loop);  // created first: it inherits this thread's CPUs before they shrink
  if (r.o.cpu >= 0) {
    if (const std::string w = keepOffCpu(r.o.cpu); !w.empty()) std::fprintf(stderr, "firmware_sim: %s\n", w.c_str());
  }
  // Communication thread: LCM in, drained queues out, statistics at a low rate.
  pollfd fds[2] = {{r.bridge.fd(), POLLIN, 0}, {efd, POLLIN, 0}};  // fd -1 (memq://): poll skips it
  std::int64_t next_stats = nowNs() + std::llround(r.o.stats_period * 1e9);
  bool warned = false;
  auto drainOut = [&] {
    Outbound ob;
    while (out.pop(ob)) {
      r.bridge.publish(ob.attitude);  // before the status, so a controller has it when the status comes
      if (ob.has_status) r.bridge.publish(ob.status);
      if (ob.has_truth) {
        r.bridge.publish(ob.truth);
        if (!r.csv.write(ob.truth)) g_stop.store(true);  // a failed write stops the run (exit 4)
      }
    }
  };
  while (!loop_done.load()) {
    const int rc = poll(fds, 2, 100);
    if (rc > 0 && (fds[0].revents & POLLIN)) r.bridge.drain();  // bounded: the statuses below still go out
    if (rc > 0 && (fds[1].revents & POLLIN)) {
      std::uint64_t v;
      [[maybe_unused]] const ssize_t n = ::read(efd, &v, sizeof v);
    }
    drainOut();
    if (!warned && setup_done.load(std::memory_order_acquire)) {
      printWarnings(r.rt_warnings);
      warned = true;
    }
    if (nowNs() >= next_stats) {
      r.bridge.publishStats(nowNs(CLOCK_REALTIME) / 1000, r.stats, warned && r.fifo, false);
      next_stats += std::llround(r.o.stats_period * 1e9);
    }
  }
  rt.join();
  drainOut();
  r.wall_seconds = static_cast<double>(nowNs() - wall0) * 1e-9;
  if (!warned) printWarnings(r.rt_warnings);
  r.bridge.publishStats(nowNs(CLOCK_REALTIME) / 1000, r.stats, r.fifo, false);
  ::close(efd);
  return finish(r, outcomeOf(fw));
}

}  // namespace

int runRealtime(Run& r) {
  return dispatchVariant(r.plant.scene.model, [&](auto tag) { return run<decltype(tag)>(r); });
}

}  // namespace gimbalsim::firmware
