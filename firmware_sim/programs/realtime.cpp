#include "realtime.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/prctl.h>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace gimbalsim::firmware {

std::string lockMemory() {
  if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
    return std::string("warning: mlockall failed (") + std::strerror(errno) +
           "): pages may fault during the loop; run as root or raise RLIMIT_MEMLOCK";
  }
  return {};
}

CpuLatencyRequest::CpuLatencyRequest(int us) {
  if (us < 0) return;
  // The request lasts while the file stays open; the value is a binary s32.
  fd_ = ::open("/dev/cpu_dma_latency", O_WRONLY | O_CLOEXEC);
  const std::int32_t value = us;
  if (fd_ < 0 || ::write(fd_, &value, sizeof value) != static_cast<ssize_t>(sizeof value)) {
    warning_ = "warning: cannot hold idle CPUs to " + std::to_string(us) + " us of wake-up latency (/dev/cpu_dma_latency: " +
               std::strerror(errno) + "): a wake-up may first wait for a halted CPU; run as root, or "
               "--cpu-dma-latency-us -1 to not ask";
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }
}

CpuLatencyRequest::~CpuLatencyRequest() {
  if (fd_ >= 0) ::close(fd_);
}

namespace {
// Touch the stack once so its pages are resident (with mlockall, for good).
__attribute__((noinline)) void prefaultStack(std::size_t bytes) {
  volatile unsigned char* p = static_cast<volatile unsigned char*>(__builtin_alloca(bytes));
  for (std::size_t i = 0; i < bytes; i += 4096) p[i] = 0;
}
}  // namespace

std::vector<std::string> setUpRealtimeThread(int priority, int cpu, std::size_t stack_bytes, bool* fifo) {
  std::vector<std::string> warnings;
  *fifo = false;
  if (priority > 0) {
    sched_param sp{};
    sp.sched_priority = priority;
    const int rc = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp);
    if (rc == 0) {
      *fifo = true;
    } else {
      warnings.push_back(std::string("warning: SCHED_FIFO priority ") + std::to_string(priority) +
                         " refused (" + std::strerror(rc) +
                         "); running SCHED_OTHER, expect larger wake-up lateness (run as root or with "
                         "CAP_SYS_NICE / an rtprio limit)");
    }
  }
  if (cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(cpu, &set);
    const int rc = pthread_setaffinity_np(pthread_self(), sizeof set, &set);
    if (rc != 0) {
      warnings.push_back("warning: cannot pin the real-time thread to CPU " + std::to_string(cpu) + " (" +
                         std::strerror(rc) + "); not pinned");
    }
  }
  if (prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL) != 0) {
    warnings.push_back(std::string("warning: PR_SET_TIMERSLACK failed (") + std::strerror(errno) + ")");
  }
  prefaultStack(stack_bytes);
  return warnings;
}

std::string cpuProblem(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return {};  // unknown: the pin itself warns if refused
  if (cpu < CPU_SETSIZE && CPU_ISSET(cpu, &set)) return {};
  std::string allowed;
  for (int c = 0; c < CPU_SETSIZE; ++c) {
    if (CPU_ISSET(c, &set)) allowed += (allowed.empty() ? "" : ",") + std::to_string(c);
  }
  return "--cpu " + std::to_string(cpu) + ": not a CPU this process may run on (it may use CPU " + allowed + ")";
}

std::string keepOffCpu(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (pthread_getaffinity_np(pthread_self(), sizeof set, &set) != 0 || cpu < 0 || cpu >= CPU_SETSIZE ||
      !CPU_ISSET(cpu, &set) || CPU_COUNT(&set) < 2) {
    return {};  // nothing to move away from
  }
  CPU_CLR(cpu, &set);
  const int rc = pthread_setaffinity_np(pthread_self(), sizeof set, &set);
  if (rc == 0) return {};
  return "warning: cannot keep the communication thread off CPU " + std::to_string(cpu) + " (" + std::strerror(rc) +
         "); it shares the loop thread's CPU";
}

std::int64_t sleepUntil(std::int64_t deadline_ns, std::int64_t spin_ns) {
  const timespec ts = fromNs(deadline_ns - spin_ns);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
  std::int64_t now = nowNs();
  while (now < deadline_ns) now = nowNs();
  return now;
}

}  // namespace gimbalsim::firmware
