// firmware_sim: the gimbal plant as a process that speaks LCM like the
// gimbal's firmware. Real-time mode: a periodic SCHED_FIFO thread runs the
// firmware core (firmware.hpp) on absolute deadlines, and a communication
// thread (this one) does all LCM work; the two hand data over through
// lock-free SPSC rings (no mutex, no allocation, no network on the RT side).
// Lockstep mode: one thread; tick k+1 runs once the command answering
// status k has arrived (or a timeout), utime is simulated time, and runs are
// bit-for-bit repeatable. CLI and exit codes: firmware_sim/README.md.
#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "gimbalsim/channels.hpp"
#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/dynamics/scene.hpp"
#include "gimbalsim/dynamics/simulate.hpp"
#include "gimbalsim/firmware/csv_rows.hpp"
#include "gimbalsim/firmware/firmware.hpp"
#include "gimbalsim/firmware/histogram.hpp"
#include "gimbalsim/firmware/spsc_ring.hpp"
#include "gimbalsim/gimbal_command_t.hpp"
#include "gimbalsim/gimbal_loop_stats_t.hpp"
#include "gimbalsim/gimbal_status_t.hpp"
#include "gimbalsim/gimbal_truth_t.hpp"
#include "realtime.hpp"

namespace gimbalsim::firmware {
namespace {

static_assert(int{kWatchdogTripped} == int{gimbal_status_t::FAULT_WATCHDOG_TRIPPED});
static_assert(int{kTorqueSaturated} == int{gimbal_status_t::FAULT_TORQUE_SATURATED});
static_assert(int{kCommandRejected} == int{gimbal_status_t::FAULT_COMMAND_REJECTED});
static_assert(int{kPlantFault} == int{gimbal_status_t::FAULT_PLANT_FAULT});
static_assert(int{kLockstepTimeout} == int{gimbal_status_t::FAULT_LOCKSTEP_TIMEOUT});
static_assert(kModeOff == gimbal_command_t::MODE_OFF && kModeTorque == gimbal_command_t::MODE_TORQUE);

enum ExitCode : int {
  kExitOk = 0,
  kExitInternal = 1,       ///< unexpected exception (a bug)
  kExitRefused = 2,        ///< bad flag, scene, profile or output file: nothing run
  kExitPlantFault = 3,     ///< the plant stopped on numerical trouble during the run
  kExitLcm = 4,            ///< LCM could not start (bad --lcm-url, no multicast route)
  kExitNoController = 5,   ///< lockstep: nobody answered status 0 within --start-timeout
};

std::atomic<bool> g_stop{false};
extern "C" void onSignal(int) { g_stop.store(true); }

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
  std::string lcm_url;
  std::string prefix;
  int rt_priority = 80;
  int cpu = -1;
  double spin_us = 0.0;
  double watchdog_ms = 50.0;
  double torque_sanity = 10.0;
  std::vector<double> safe_torque{0.0, 0.0};
  std::string profile;
  double stats_period = 1.0;
};

/// A command as it crosses from the communication thread to the loop.
struct Inbound {
  bool undecodable = false;
  Command cmd;
};

/// What the loop hands back each tick.
struct Outbound {
  Status status;
  bool has_truth = false;
  Truth truth;
};

/// Statistics written by the loop thread, read by the communication thread.
struct LoopStats {
  Histogram period{10000}, lateness{10000}, compute{10000};  // [us], 1 us bins to 10 ms
  std::atomic<std::int64_t> ticks{0}, overruns{0}, substeps{0}, dropped_out{0};
  std::atomic<int> substeps_max{0};

  void addSubsteps(int n) noexcept {
    substeps.store(substeps.load(std::memory_order_relaxed) + n, std::memory_order_relaxed);
    if (n > substeps_max.load(std::memory_order_relaxed)) substeps_max.store(n, std::memory_order_relaxed);
  }
};

template <std::size_t N>
void copyN(double (&dst)[N], const double (&src)[N]) {
  std::memcpy(dst, src, sizeof dst);
}

/// LCM side: decodes commands into a ring, publishes from preallocated
/// buffers with the raw publish (the typed one allocates on every call).
class Comm {
 public:
  Comm(lcm::LCM& lcm, Channels ch, SpscRing<Inbound>& in) : lcm_(lcm), ch_(std::move(ch)), in_(in) {
    for (auto& x : pub_seq_) x = -1;
    lcm_.subscribe(ch_.command, &Comm::onCommand, this);
  }

  void onCommand(const lcm::ReceiveBuffer* rb, const std::string&) {
    const std::int64_t now = nowNs();
    Inbound m;
    gimbal_command_t c;
    const int n = c.decode(rb->data, 0, static_cast<int>(rb->data_size));
    if (n < 0 || n != static_cast<int>(rb->data_size)) {
      m.undecodable = true;  // garbage, a wrong type (fingerprint mismatch) or trailing bytes
    } else {
      m.cmd.utime = c.utime;
      m.cmd.seq = c.seq;
      m.cmd.status_seq = c.status_seq;
      m.cmd.mode = c.mode;
      m.cmd.torque[0] = c.torque[0];
      m.cmd.torque[1] = c.torque[1];
      // Round trip: the first answer to a status we published.
      const std::size_t i = static_cast<std::size_t>(c.status_seq) % kRoundTripSlots;
      if (c.status_seq >= 0 && pub_seq_[i] == c.status_seq) {
        roundtrip.add(static_cast<double>(now - pub_ns_[i]) * 1e-3);
        pub_seq_[i] = -1;
      }
    }
    if (!in_.push(m)) ++dropped_in;
  }

  void publish(const Status& s) {
    gimbal_status_t o;
    o.utime = s.utime;
    o.seq = s.seq;
    copyN(o.angle, s.angle);
    copyN(o.rate, s.rate);
    copyN(o.applied_torque, s.applied_torque);
    o.faults = s.faults;
    o.last_command_seq = s.last_command_seq;
    o.commands_received = s.commands_received;
    o.commands_rejected = s.commands_rejected;
    o.commands_missed = s.commands_missed;
    send(ch_.status, o);
    const std::size_t i = static_cast<std::size_t>(s.seq) % kRoundTripSlots;
    pub_seq_[i] = s.seq;
    pub_ns_[i] = nowNs();
    last_status_ = s;
  }

  void publish(const Truth& t) {
    gimbal_truth_t o;
    o.utime = t.utime;
    o.seq = t.seq;
    o.sim_time = t.sim_time;
    copyN(o.base_position, t.base_position);
    copyN(o.base_quaternion, t.base_quaternion);
    copyN(o.base_rate, t.base_rate);
    copyN(o.base_velocity, t.base_velocity);
    copyN(o.joint_angle, t.joint_angle);
    copyN(o.joint_rate, t.joint_rate);
    copyN(o.applied_torque, t.applied_torque);
    copyN(o.eccentricity, t.eccentricity);
    o.penetration = t.penetration;
    o.contact_normal_force = t.contact_normal_force;
    o.contact_tangential_force = t.contact_tangential_force;
    o.joint2_force = t.joint2_force;
    copyN(o.boresight, t.boresight);
    copyN(o.target_boresight, t.target_boresight);
    o.pointing_error = t.pointing_error;
    copyN(o.momentum_linear, t.momentum_linear);
    copyN(o.momentum_angular, t.momentum_angular);
    o.energy = t.energy;
    o.faults = t.faults;
    send(ch_.truth, o);
  }

  void publishStats(std::int64_t utime, const LoopStats& st, bool realtime, bool lockstep) {
    gimbal_loop_stats_t o;
    o.utime = utime;
    o.ticks = st.ticks.load();
    o.period_p50 = st.period.quantile(0.5);
    o.period_p99 = st.period.quantile(0.99);
    o.period_p999 = st.period.quantile(0.999);
    o.period_max = st.period.max();
    o.lateness_p50 = st.lateness.quantile(0.5);
    o.lateness_p99 = st.lateness.quantile(0.99);
    o.lateness_p999 = st.lateness.quantile(0.999);
    o.lateness_max = st.lateness.max();
    o.compute_p50 = st.compute.quantile(0.5);
    o.compute_p99 = st.compute.quantile(0.99);
    o.compute_max = st.compute.max();
    o.overruns = st.overruns.load();
    o.roundtrip_p50 = roundtrip.quantile(0.5);
    o.roundtrip_p99 = roundtrip.quantile(0.99);
    o.roundtrip_p999 = roundtrip.quantile(0.999);
    o.roundtrip_max = roundtrip.max();
    o.substeps_mean = o.ticks > 0 ? static_cast<double>(st.substeps.load()) / o.ticks : 0.0;
    o.substeps_max = st.substeps_max.load();
    o.commands_received = last_status_.commands_received;
    o.commands_rejected = last_status_.commands_rejected;
    o.commands_missed = last_status_.commands_missed;
    o.realtime = realtime ? 1 : 0;
    o.lockstep = lockstep ? 1 : 0;
    send(ch_.loop_stats, o);
  }

  /// Status published -> command answering it received [us] (this thread only).
  Histogram roundtrip{10000};
  long long dropped_in = 0;  ///< commands lost because the inbound ring was full
  long long publish_errors = 0;

 private:
  template <class M>
  void send(const std::string& channel, const M& msg) {
    const int n = msg.encode(buf_, 0, sizeof buf_);
    if (n < 0 || lcm_.publish(channel, buf_, static_cast<unsigned>(n)) != 0) ++publish_errors;
  }

  lcm::LCM& lcm_;
  Channels ch_;
  SpscRing<Inbound>& in_;
  Status last_status_;
  unsigned char buf_[2048];
  static constexpr std::size_t kRoundTripSlots = 1024;
  std::int64_t pub_seq_[kRoundTripSlots];  ///< seq of the status published in each slot (-1: answered)
  std::int64_t pub_ns_[kRoundTripSlots];   ///< when it was published [ns, CLOCK_MONOTONIC]
};

/// Every truth message as one CSV row (csv_rows.hpp: %.17g, so a row
/// round-trips exactly; gimbalsim_log2csv writes the same bytes from a log).
class TruthCsv {
 public:
  bool open(const std::string& path) {
    f_ = std::fopen(path.c_str(), "w");
    if (!f_) return false;
    std::fputs(csv::kTruthHeader, f_);
    return true;
  }
  void write(const Truth& t) {
    if (f_) csv::writeTruthRow(f_, t);
  }
  bool close() {
    if (!f_) return true;
    const bool ok = std::fclose(f_) == 0;
    f_ = nullptr;
    return ok;
  }
  ~TruthCsv() { close(); }

 private:
  std::FILE* f_ = nullptr;
};

struct Run {
  const Model& m;
  const Options& o;
  const Config& c;
  const controllers::TargetProfile* profile;
  lcm::LCM& lcm;
  Comm& comm;
  SpscRing<Inbound>& in;
  TruthCsv& csv;
  LoopStats stats;
  bool fifo = false;
  std::vector<std::string> rt_warnings;
  double wall_seconds = 0.0;
  long long lockstep_timeouts = 0;
};

std::int64_t totalTicks(const Options& o, const Config& c) {
  return o.duration > 0.0 ? static_cast<std::int64_t>(std::llround(o.duration / c.control_period)) : -1;
}

template <class V>
void drainInbound(Firmware<V>& fw, SpscRing<Inbound>& in, std::int64_t answer_to = -2, bool* answered = nullptr) {
  Inbound m;
  while (in.pop(m)) {
    if (m.undecodable) {
      fw.receiveUndecodable();
    } else {
      fw.receive(m.cmd);
      if (answered && m.cmd.status_seq == answer_to) *answered = true;
    }
  }
}

template <class V>
void printExitSummary(const Run& r, const Firmware<V>& fw) {
  const LoopStats& st = r.stats;
  const Counters& n = fw.counters();
  const double sim_s = static_cast<double>(fw.ticks()) * r.c.control_period;
  std::printf("firmware_sim: %lld ticks, %.3f s simulated in %.3f s wall (%.2f x real time), %s\n",
              static_cast<long long>(fw.ticks()), sim_s, r.wall_seconds,
              r.wall_seconds > 0 ? sim_s / r.wall_seconds : 0.0,
              r.o.lockstep ? "lockstep" : (r.fifo ? "real time, SCHED_FIFO" : "real time, SCHED_OTHER"));
  if (!r.o.lockstep) {
    std::printf("  wake-up lateness [us]: p50 %.0f  p99 %.0f  p99.9 %.0f  max %.1f\n", st.lateness.quantile(0.5),
                st.lateness.quantile(0.99), st.lateness.quantile(0.999), st.lateness.max());
    std::printf("  tick period [us]:      p50 %.0f  p99 %.0f  p99.9 %.0f  max %.1f\n", st.period.quantile(0.5),
                st.period.quantile(0.99), st.period.quantile(0.999), st.period.max());
  }
  std::printf("  compute per tick [us]: p50 %.0f  p99 %.0f  max %.1f   (1 us bins)\n", st.compute.quantile(0.5),
              st.compute.quantile(0.99), st.compute.max());
  const long long t = st.ticks.load();
  const Histogram& rt = r.comm.roundtrip;
  if (rt.count() > 0) {
    std::printf("  status -> command round trip [us]: p50 %.0f  p99 %.0f  p99.9 %.0f  max %.1f  (%llu answers)\n",
                rt.quantile(0.5), rt.quantile(0.99), rt.quantile(0.999), rt.max(),
                static_cast<unsigned long long>(rt.count()));
  }
  std::printf("  overruns %lld; RK4 sub-steps per tick: mean %.2f, max %d\n", static_cast<long long>(st.overruns.load()),
              t > 0 ? static_cast<double>(st.substeps.load()) / t : 0.0, st.substeps_max.load());
  std::printf("  commands: received %lld, rejected %lld, missed %lld; watchdog trips %lld; saturated ticks %lld\n",
              static_cast<long long>(n.received), static_cast<long long>(n.rejected), static_cast<long long>(n.missed),
              static_cast<long long>(n.watchdog_trips), static_cast<long long>(n.saturated_ticks));
  for (int i = 1; i < kNumRejections; ++i) {
    if (n.by_reason[i] > 0) {
      std::printf("    rejected %lld: %s\n", static_cast<long long>(n.by_reason[i]), describe(static_cast<Rejection>(i)));
    }
  }
  if (r.o.lockstep) std::printf("  lockstep timeouts %lld\n", r.lockstep_timeouts);
  if (st.dropped_out.load() > 0 || r.comm.dropped_in > 0 || r.comm.publish_errors > 0) {
    std::printf("  lost: %lld outbound (ring full), %lld inbound (ring full), %lld publish errors\n",
                static_cast<long long>(st.dropped_out.load()), r.comm.dropped_in, r.comm.publish_errors);
  }
  std::fflush(stdout);
}

template <class V>
int reportPlantFault(const Model& m, const Firmware<V>& fw) {
  if (!fw.plantFault()) return kExitOk;
  const std::vector<std::string> names = coordinateNamesV(m);
  const int i = fw.plantFailIndex();
  std::fprintf(stderr,
               "firmware_sim: PLANT FAULT at t = %.9g s: %s%s%s; the state was frozen at the last good one "
               "and every later status carried FAULT_PLANT_FAULT\n",
               fw.plantFailTime(), describe(fw.plantStatus()), i >= 0 ? " in coordinate " : "",
               i >= 0 && i < static_cast<int>(names.size()) ? names[i].c_str() : "");
  return kExitPlantFault;
}

// ---------------------------------------------------------------- real time
template <class V>
int runRealtime(Run& r) {
  Firmware<V> fw(r.m, r.c, r.profile);
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
    // Start on a whole period boundary a little ahead, so set-up does not count as lateness.
    std::int64_t next = (nowNs() / period_ns + 2) * period_ns;
    std::int64_t prev_wake = -1;
    for (std::int64_t k = 0; (total < 0 || k < total) && !g_stop.load(std::memory_order_relaxed); ++k) {
      const std::int64_t wake = sleepUntil(next, spin_ns);
      r.stats.lateness.add(static_cast<double>(wake - next) * 1e-3);
      if (prev_wake >= 0) r.stats.period.add(static_cast<double>(wake - prev_wake) * 1e-3);
      prev_wake = wake;

      drainInbound(fw, r.in);
      const std::int64_t utime = nowNs(CLOCK_REALTIME) / 1000;
      const bool want_truth = k % truth_every == 0;
      fw.sample(utime, want_truth);
      Outbound ob;
      ob.status = fw.status();
      ob.has_truth = want_truth;
      if (want_truth) ob.truth = fw.truth();
      if (!out.push(ob)) r.stats.dropped_out.fetch_add(1, std::memory_order_relaxed);
      const std::uint64_t one = 1;
      [[maybe_unused]] const ssize_t w = ::write(efd, &one, sizeof one);  // wakes the communication thread
      fw.advance();

      const std::int64_t end = nowNs();
      r.stats.compute.add(static_cast<double>(end - wake) * 1e-3);
      r.stats.addSubsteps(fw.lastSubsteps());
      r.stats.ticks.store(k + 1, std::memory_order_relaxed);
      next += period_ns;
      if (end > next) {  // the work ran past the next deadline: skip the missed ones
        const std::int64_t missed = (end - next) / period_ns + 1;
        r.stats.overruns.fetch_add(missed, std::memory_order_relaxed);
        next += missed * period_ns;
      }
    }
    loop_done.store(true);
    const std::uint64_t one = 1;
    [[maybe_unused]] const ssize_t w = ::write(efd, &one, sizeof one);
  };

  const std::int64_t wall0 = nowNs();
  std::thread rt(loop);
  // Communication thread: LCM in, drained rings out, statistics at a low rate.
  pollfd fds[2] = {{r.lcm.getFileno(), POLLIN, 0}, {efd, POLLIN, 0}};
  std::int64_t next_stats = nowNs() + std::llround(r.o.stats_period * 1e9);
  bool warned = false;
  auto drainOut = [&] {
    Outbound ob;
    while (out.pop(ob)) {
      r.comm.publish(ob.status);
      if (ob.has_truth) {
        r.comm.publish(ob.truth);
        r.csv.write(ob.truth);
      }
    }
  };
  while (!loop_done.load()) {
    const int rc = poll(fds, 2, 100);
    if (rc > 0 && (fds[0].revents & POLLIN)) r.lcm.handle();
    if (rc > 0 && (fds[1].revents & POLLIN)) {
      std::uint64_t v;
      [[maybe_unused]] const ssize_t n = ::read(efd, &v, sizeof v);
    }
    drainOut();
    if (!warned && setup_done.load(std::memory_order_acquire)) {
      for (const std::string& w : r.rt_warnings) std::fprintf(stderr, "firmware_sim: %s\n", w.c_str());
      warned = true;
    }
    if (nowNs() >= next_stats) {
      r.comm.publishStats(nowNs(CLOCK_REALTIME) / 1000, r.stats, warned && r.fifo, false);
      next_stats += std::llround(r.o.stats_period * 1e9);
    }
  }
  rt.join();
  drainOut();
  r.wall_seconds = static_cast<double>(nowNs() - wall0) * 1e-9;
  if (!warned) {
    for (const std::string& w : r.rt_warnings) std::fprintf(stderr, "firmware_sim: %s\n", w.c_str());
  }
  r.comm.publishStats(nowNs(CLOCK_REALTIME) / 1000, r.stats, r.fifo, false);
  ::close(efd);
  printExitSummary(r, fw);
  return reportPlantFault(r.m, fw);
}

// ----------------------------------------------------------------- lockstep
template <class V>
int runLockstep(Run& r) {
  Firmware<V> fw(r.m, r.c, r.profile);
  const std::int64_t total = totalTicks(r.o, r.c);
  const std::int64_t wall0 = nowNs();
  std::int32_t extra = 0;
  std::int64_t next_stats = wall0 + std::llround(r.o.stats_period * 1e9);
  for (std::int64_t k = 0; (total < 0 || k < total) && !g_stop.load(); ++k) {
    const std::int64_t t0 = nowNs();
    drainInbound(fw, r.in);
    const std::int64_t utime = std::llround(static_cast<double>(k) * r.c.control_period * 1e6);
    const bool want_truth = k % r.o.truth_every == 0;
    fw.sample(utime, want_truth, extra);
    extra = 0;
    r.comm.publish(fw.status());
    if (want_truth) {
      r.comm.publish(fw.truth());
      r.csv.write(fw.truth());
    }
    fw.advance();
    r.stats.compute.add(static_cast<double>(nowNs() - t0) * 1e-3);
    r.stats.addSubsteps(fw.lastSubsteps());
    r.stats.ticks.store(k + 1, std::memory_order_relaxed);
    if (nowNs() >= next_stats) {
      r.comm.publishStats(utime, r.stats, false, true);
      next_stats = nowNs() + std::llround(r.o.stats_period * 1e9);
    }
    if (total >= 0 && k + 1 >= total) break;  // the last status needs no answer

    // Wait for the command answering status k (for status 0: re-publish it
    // until a controller answers, up to the start timeout).
    const bool first = k == 0;
    const std::int64_t wait_ns = first ? std::llround(r.o.start_timeout_s * 1e9) : std::llround(r.o.lockstep_timeout_ms * 1e6);
    const std::int64_t deadline = nowNs() + wait_ns;
    std::int64_t republish = nowNs() + 200000000;
    bool answered = false;
    while (!answered && !g_stop.load()) {
      drainInbound(fw, r.in, k, &answered);
      if (answered) break;
      const std::int64_t now = nowNs();
      if (now >= deadline) break;
      if (first && now >= republish) {
        r.comm.publish(fw.status());
        republish = now + 200000000;
      }
      const std::int64_t until = first ? std::min(deadline, republish) : deadline;
      const int ms = static_cast<int>(std::max<std::int64_t>(1, (until - now + 999999) / 1000000));
      if (r.lcm.handleTimeout(ms) < 0 && !g_stop.load()) {  // (a signal also interrupts it)
        std::fprintf(stderr, "firmware_sim: LCM receive failed\n");
        g_stop.store(true);
      }
    }
    if (!answered && !g_stop.load()) {
      if (first) {
        std::fprintf(stderr,
                     "firmware_sim: lockstep: no command answering status 0 arrived within --start-timeout %g s "
                     "on channel %s; is the controller running with the same --lcm-url and --channel-prefix?\n",
                     r.o.start_timeout_s, (r.o.prefix + Channels::kCommand).c_str());
        r.wall_seconds = static_cast<double>(nowNs() - wall0) * 1e-9;
        printExitSummary(r, fw);
        return kExitNoController;
      }
      extra = kLockstepTimeout;
      ++r.lockstep_timeouts;
    }
  }
  r.wall_seconds = static_cast<double>(nowNs() - wall0) * 1e-9;
  r.comm.publishStats(std::llround(static_cast<double>(fw.ticks()) * r.c.control_period * 1e6), r.stats, false, true);
  printExitSummary(r, fw);
  return reportPlantFault(r.m, fw);
}

int refuse(const std::string& what) {
  std::fprintf(stderr, "firmware_sim: error: %s\nfirmware_sim: refused, nothing run (exit 2)\n", what.c_str());
  return kExitRefused;
}

int mainImpl(int argc, char** argv) {
  Options o;
  CLI::App app{"firmware_sim: the gimbal plant speaking LCM like its firmware (real time or lockstep)"};
  app.add_option("scene", o.scene, "scene file (YAML), e.g. tools/scenes/paper_clearance.yaml")->required();
  app.add_option("--set", o.sets, "scene override key=value (repeatable); see `gimbalsim keys`");
  app.add_option("--rate", o.rate_hz, "control rate [Hz]; 1/rate must be a whole multiple of sim.step")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--duration", o.duration, "simulated seconds to run (0 = until SIGINT/SIGTERM)")
      ->capture_default_str()->check(CLI::NonNegativeNumber);
  app.add_flag("--lockstep", o.lockstep, "lockstep: tick k+1 waits for the command answering status k");
  app.add_option("--lockstep-timeout-ms", o.lockstep_timeout_ms, "lockstep: wait at most this for an answer [ms]")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--start-timeout", o.start_timeout_s, "lockstep: wait at most this for the first answer [s]")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--truth-every", o.truth_every, "publish truth every N ticks")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--truth-csv", o.truth_csv, "write every truth message to this CSV file");
  app.add_option("--lcm-url", o.lcm_url, "LCM provider URL (default: LCM_DEFAULT_URL or LCM's default)");
  app.add_option("--channel-prefix", o.prefix, "prefix of every channel name, e.g. BENCH2_");
  app.add_option("--rt-priority", o.rt_priority, "SCHED_FIFO priority of the loop thread (0 = SCHED_OTHER)")
      ->capture_default_str()->check(CLI::Range(0, 99));
  app.add_option("--cpu", o.cpu, "pin the loop thread to this CPU (-1 = no pin)")->capture_default_str()->check(CLI::Range(-1, 1023));
  app.add_option("--spin-us", o.spin_us, "busy-wait the last N us before each deadline")
      ->capture_default_str()->check(CLI::Range(0.0, 100000.0));
  app.add_option("--watchdog-ms", o.watchdog_ms, "no valid command for this long -> safe command [ms]")
      ->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--torque-sanity", o.torque_sanity, "reject commands with |torque| > this x torque.limit")
      ->capture_default_str()->check(CLI::Range(1.0, 1e6));
  app.add_option("--safe-torque", o.safe_torque, "torque applied while the watchdog is tripped [N m] (2 values)")
      ->expected(2)->capture_default_str();
  app.add_option("--profile", o.profile, "controller config file whose target profile defines the pointing error");
  app.add_option("--stats-period", o.stats_period, "loop statistics publication period [s]")
      ->capture_default_str()->check(CLI::PositiveNumber);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::printf("%s", app.help().c_str());
    return kExitOk;
  } catch (const CLI::ParseError& e) {
    return refuse(std::string(e.what()) + " (see --help)");
  }

  LoadedScene scene;
  try {
    scene = loadScene(o.scene, o.sets);
  } catch (const SceneError& e) {
    for (const std::string& p : e.problems()) std::fprintf(stderr, "error: %s\n", p.c_str());
    return refuse("scene " + o.scene + " refused");
  }
  for (const std::string& w : scene.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  const Model& m = scene.model;

  Config c;
  c.control_period = 1.0 / o.rate_hz;
  c.watchdog_timeout = o.watchdog_ms * 1e-3;
  c.torque_sanity_factor = o.torque_sanity;
  c.safe_torque = Vec2(o.safe_torque[0], o.safe_torque[1]);
  if (const std::string err = checkConfig(m, c, nullptr); !err.empty()) {
    const bool rate = err.rfind("control period", 0) == 0;
    return refuse(rate ? "--rate " + CLI::detail::to_string(o.rate_hz) + ": " + err : err);
  }
  if (!Channels::validPrefix(o.prefix)) {
    return refuse("--channel-prefix '" + o.prefix + "': only A-Z, 0-9 and '_' (channel names are UPPER_SNAKE)");
  }
  std::unique_ptr<controllers::TargetProfile> profile;
  if (!o.profile.empty()) {
    try {
      profile = std::make_unique<controllers::TargetProfile>(controllers::loadControllerConfig(o.profile).profile);
    } catch (const SceneError& e) {
      for (const std::string& p : e.problems()) std::fprintf(stderr, "error: %s\n", p.c_str());
      return refuse("--profile " + o.profile + " refused");
    }
  }
  TruthCsv csv;
  if (!o.truth_csv.empty() && !csv.open(o.truth_csv)) {
    return refuse("--truth-csv " + o.truth_csv + ": cannot open for writing (" + std::strerror(errno) + ")");
  }

  if (!o.lockstep) {
    if (const std::string w = lockMemory(); !w.empty()) std::fprintf(stderr, "firmware_sim: %s\n", w.c_str());
  }
  lcm::LCM lcm(o.lcm_url);
  if (!lcm.good()) {
    std::fprintf(stderr,
                 "firmware_sim: error: LCM could not start with URL '%s' (check --lcm-url / LCM_DEFAULT_URL; "
                 "udpm needs a multicast route, e.g. `ip route add 224.0.0.0/4 dev lo`)\n",
                 o.lcm_url.c_str());
    return kExitLcm;
  }
  SpscRing<Inbound> in(1024);
  Comm comm(lcm, Channels::withPrefix(o.prefix), in);

  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  std::fprintf(stderr, "firmware_sim: scene '%s' (%s), %g Hz (%d RK4 steps of %g s per tick), %s, channels %s*\n",
               m.name.c_str(), variantName(m).c_str(), o.rate_hz, static_cast<int>(std::llround(c.control_period / m.integrator.step)),
               m.integrator.step, o.lockstep ? "lockstep" : "real time", (o.prefix + "GIMBAL_").c_str());

  Run r{m, o, c, profile.get(), lcm, comm, in, csv, {}, false, {}, 0.0, 0};
  const int rc = dispatchVariant(m, [&](auto tag) {
    using V = decltype(tag);
    return o.lockstep ? runLockstep<V>(r) : runRealtime<V>(r);
  });
  if (!csv.close()) {
    std::fprintf(stderr, "firmware_sim: error: writing %s failed\n", o.truth_csv.c_str());
    return rc == kExitOk ? kExitInternal : rc;
  }
  return rc;
}

}  // namespace
}  // namespace gimbalsim::firmware

int main(int argc, char** argv) {
  try {
    return gimbalsim::firmware::mainImpl(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "firmware_sim: internal error: %s\n", e.what());
    return 1;
  }
}
