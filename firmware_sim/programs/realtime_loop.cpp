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
#include "gimbalsim/firmware_sim/spsc_ring.hpp"
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

constexpr std::size_t kInboundCapacity = 1024;  ///< decoded commands between two ticks

/// Real time's command intake: the communication thread pushes, the loop
/// thread pops at the tick's start.
class RingSink final : public CommandSink {
 public:
  bool take(const Inbound& m) noexcept override { return ring.push(m); }
  SpscRing<Inbound> ring{kInboundCapacity};
};

/// Hands every queued command to the firmware (loop thread).
template <class V>
void drainInbound(Firmware<V>& fw, SpscRing<Inbound>& in) noexcept {
  Inbound m;
  while (in.pop(m)) deliver(fw, m);
}

/// What the loop thread hands to the communication thread each tick.
struct Outbound {
  bool has_attitude = true;  ///< false at the run's end (a truth only)
  Attitude attitude;
  bool has_antenna = false;  ///< the scene has antenna sensors (sensors.antenna)
  Antenna antenna;
  bool has_status = true;  ///< false: a scheduled status drop or delay left none this tick
  Status status;
  bool has_truth = false;
  Truth truth;
};

template <class V>
int run(Run& r) {
  const Options& o = r.setup.o;
  BenchTick<V> tick(r.setup.plant, r.setup.c, r.setup.faults, r.setup.profile);
  Firmware<V>& fw = tick.firmware();
  RingSink in;
  const SinkBinding bound(r.ports.bridge, &in);
  SpscRing<Outbound> out(4096);
  const int efd = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (efd < 0) {
    std::fprintf(stderr, "firmware_sim: eventfd failed: %s\n", std::strerror(errno));
    return kExitInternal;
  }
  const std::int64_t total = totalTicks(o, r.setup.c);
  const std::int64_t period_ns = std::llround(r.setup.c.control_period * 1e9);
  const std::int64_t spin_ns = std::llround(o.spin_us * 1e3);
  const int truth_every = o.truth_every;
  std::atomic<bool> loop_done{false};
  std::atomic<bool> setup_done{false};  // publishes r.report.rt_warnings and .fifo to this thread
  RunReport& rep = r.report;

  auto loop = [&] {
    rep.rt_warnings = setUpRealtimeThread(o.rt_priority, o.cpu, 256 * 1024, &rep.fifo);
    setup_done.store(true, std::memory_order_release);
    warmUp(fw);
    // Start on a whole period boundary a little ahead, so set-up does not count as lateness.
    std::int64_t next = (nowNs() / period_ns + 2) * period_ns;
    const std::int64_t realtime_offset = nowNs(CLOCK_REALTIME) - nowNs();  // stamps: the deadline on the wall clock
    std::int64_t prev_wake = -1;
    // k = total is the run's end: the plant's state at T, sampled but never
    // stepped; only its truth goes out (as lockstep's), so the CSV holds t = 0 .. T.
    for (std::int64_t k = 0; (total < 0 || k <= total) && !g_stop.load(std::memory_order_relaxed); ++k) {
      const bool end = k == total;
      const std::int64_t start_ns = nowNs();
      const bool late = start_ns > next;  // the previous tick overran this deadline: catch up
      TickTimes tt{};
      tt.wall_start = start_ns;
      // The run's end is no tick: its wake-up stays out of the tick statistics.
      if (late && !end) {
        rep.stats.late.add(static_cast<double>(start_ns - next) * 1e-4);  // [10 us]
        rep.stats.late_ticks.fetch_add(1, std::memory_order_relaxed);
      } else if (!late) {
        tt.wall_start = sleepUntil(next, spin_ns);
        if (!end) rep.stats.lateness.add(static_cast<double>(tt.wall_start - next) * 1e-3);
        if (prev_wake >= 0 && !end) rep.stats.period.add(static_cast<double>(tt.wall_start - prev_wake) * 1e-3);
        prev_wake = tt.wall_start;
      }
      // Read after the wake-up and before the end: the CPU span lies inside the wall span
      // and, like it, counts the command intake.
      tt.cpu_start = nowNs(CLOCK_THREAD_CPUTIME_ID);
      if (!late) drainInbound(fw, in.ring);  // catch-up ticks hold the last accepted command
      // Real time's clock: utime is the tick's deadline on the wall clock.
      const TickMessages m = tick.sample(k, (next + realtime_offset) / 1000, k % truth_every == 0);
      Outbound ob;
      ob.has_attitude = !end;
      ob.attitude = *m.attitude;
      ob.has_antenna = m.antenna != nullptr;
      if (m.antenna) ob.antenna = *m.antenna;
      ob.has_status = m.status != nullptr && !end;
      if (m.status) ob.status = *m.status;
      ob.has_truth = m.truth != nullptr;
      if (m.truth) ob.truth = *m.truth;
      if (!out.push(ob)) rep.stats.dropped_out.fetch_add(1, std::memory_order_relaxed);
      wake(efd);  // the communication thread
      if (end) break;
      tt.cpu_step = nowNs(CLOCK_THREAD_CPUTIME_ID);
      tick.advance();
      tt.cpu_end = nowNs(CLOCK_THREAD_CPUTIME_ID);
      tt.wall_end = nowNs();
      account(r, fw, k, tt);
      next += period_ns;
      if (tt.wall_end > next) rep.stats.overruns.fetch_add(1, std::memory_order_relaxed);  // the next tick starts late
    }
    loop_done.store(true);
    wake(efd);
  };

  const std::int64_t wall0 = nowNs();
  std::thread rt(loop);  // created first: it inherits this thread's CPUs before they shrink
  if (o.cpu >= 0) {
    if (const std::string w = keepOffCpu(o.cpu); !w.empty()) std::fprintf(stderr, "firmware_sim: %s\n", w.c_str());
  }
  // Communication thread: LCM in, drained queues out, statistics at a low rate.
  LcmBridge& bridge = r.ports.bridge;
  pollfd fds[2] = {{bridge.fd(), POLLIN, 0}, {efd, POLLIN, 0}};  // fd -1 (memq://): poll skips it
  std::int64_t next_stats = nowNs() + std::llround(o.stats_period * 1e9);
  bool warned = false;
  auto drainOut = [&] {
    Outbound ob;
    while (out.pop(ob)) {
      if (ob.has_attitude) bridge.publish(ob.attitude);  // before the status, so a controller has it when the status comes
      if (ob.has_antenna) bridge.publish(ob.antenna);
      if (ob.has_status) bridge.publish(ob.status);
      bridge.flush();  // what a controller answers, in one system call; the truth after (as lockstep)
      if (ob.has_truth) {
        bridge.publish(ob.truth);
        bridge.flush();
        // a failed write stops the run (exit 4)
        if (!r.ports.csv.write(ob.truth, ob.has_antenna ? &ob.antenna : nullptr)) g_stop.store(true);
      }
    }
  };
  while (!loop_done.load()) {
    const int rc = poll(fds, 2, 100);
    if (rc > 0 && (fds[0].revents & POLLIN)) bridge.drain();  // bounded: the statuses below still go out
    if (rc > 0 && (fds[1].revents & POLLIN)) {
      std::uint64_t v;
      [[maybe_unused]] const ssize_t n = ::read(efd, &v, sizeof v);
    }
    drainOut();
    if (!warned && setup_done.load(std::memory_order_acquire)) {
      printWarnings(rep.rt_warnings);
      warned = true;
    }
    if (nowNs() >= next_stats) {
      bridge.publishStats(nowNs(CLOCK_REALTIME) / 1000, rep.stats, warned && rep.fifo, false);
      bridge.flush();
      next_stats += std::llround(o.stats_period * 1e9);
    }
  }
  rt.join();
  drainOut();
  rep.wall_seconds = static_cast<double>(nowNs() - wall0) * 1e-9;
  rep.pointing = tick.pointing();
  if (!warned) printWarnings(rep.rt_warnings);
  bridge.publishStats(nowNs(CLOCK_REALTIME) / 1000, rep.stats, rep.fifo, false);
  bridge.flush();
  ::close(efd);
  return finish(r, outcomeOf(fw));
}

}  // namespace

int runRealtime(Run& r) {
  return dispatchVariant(r.setup.plant.scene.model, [&](auto tag) { return run<decltype(tag)>(r); });
}

}  // namespace gimbalsim::firmware
