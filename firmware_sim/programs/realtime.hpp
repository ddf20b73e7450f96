// Process and thread set-up for the real-time loop, and monotonic time helpers.
// Each set-up step reports what it could not do as one plain line; none fails
// the program (a bench without privileges still runs, with worse latency).
#pragma once

#include <cstdint>
#include <ctime>
#include <string>
#include <vector>

namespace gimbalsim::firmware {

/// mlockall(MCL_CURRENT | MCL_FUTURE). Empty on success, else a warning line.
std::string lockMemory();

/// The kernel's CPU latency request (PM QoS, /dev/cpu_dma_latency), held
/// while this object lives: idle CPUs keep to idle states that wake within
/// `us` microseconds (0: they poll instead of halting, as cyclictest asks),
/// so a deadline does not first wait for a halted CPU to come back, which a
/// virtual machine's halt makes cost tens of microseconds. us < 0: no request.
class CpuLatencyRequest {
 public:
  explicit CpuLatencyRequest(int us);
  ~CpuLatencyRequest();
  CpuLatencyRequest(const CpuLatencyRequest&) = delete;
  CpuLatencyRequest& operator=(const CpuLatencyRequest&) = delete;
  /// Empty when held (or none asked), else a warning line.
  const std::string& warning() const { return warning_; }
  bool held() const { return fd_ >= 0; }

 private:
  int fd_ = -1;
  std::string warning_;
};

/// For the calling thread: SCHED_FIFO at `priority` (0: leave SCHED_OTHER),
/// pin to `cpu` (-1: no pin), timer slack 1 ns, prefault `stack_bytes` of stack.
/// Returns the warnings; *fifo says whether SCHED_FIFO was granted.
std::vector<std::string> setUpRealtimeThread(int priority, int cpu, std::size_t stack_bytes, bool* fifo);

/// Why `cpu` cannot take the loop thread (not one this process may run on: the CPUs it may use are
/// named), or empty.
std::string cpuProblem(int cpu);

/// For the calling thread: every CPU it may run on except `cpu`, so its
/// system calls and the network work they start (loopback delivery runs in
/// softirq on the sender's CPU) stay off the loop thread's CPU. Empty on
/// success or when `cpu` is the only one allowed, else a warning line.
std::string keepOffCpu(int cpu);

inline std::int64_t toNs(const timespec& t) { return std::int64_t{t.tv_sec} * 1000000000 + t.tv_nsec; }
inline timespec fromNs(std::int64_t ns) {
  timespec t;
  t.tv_sec = static_cast<time_t>(ns / 1000000000);
  t.tv_nsec = static_cast<long>(ns % 1000000000);
  return t;
}
inline std::int64_t nowNs(clockid_t clock = CLOCK_MONOTONIC) {
  timespec t;
  clock_gettime(clock, &t);
  return toNs(t);
}

/// Sleeps until `deadline_ns` on CLOCK_MONOTONIC (absolute), the last
/// `spin_ns` by busy-waiting. Returns the wake-up time [ns].
std::int64_t sleepUntil(std::int64_t deadline_ns, std::int64_t spin_ns);

}  // namespace gimbalsim::firmware
