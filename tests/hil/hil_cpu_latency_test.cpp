// firmware_sim in real time holds the kernel's CPU latency request
// (/dev/cpu_dma_latency, PM QoS) for exactly its run, at the value asked,
// as cyclictest does: idle CPUs then wake without a halt's exit cost.
// Lockstep holds it too (a CPU that halts between ticks comes back slower
// than the tick budget was timed); -1 asks nothing. The kernel's value is
// the smallest request held, read while the process runs (memq://: no
// network, no controller). Skipped where the file is not readable (root
// only) or another process already holds a request.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <thread>

#include "hil_util.hpp"

namespace gimbalsim::hil {
namespace {

/// The kernel's CPU latency target [us], or -1 when it cannot be read.
std::int32_t cpuLatencyNow() {
  const int fd = ::open("/dev/cpu_dma_latency", O_RDONLY | O_CLOEXEC);
  if (fd < 0) return -1;
  std::int32_t v = -1;
  const bool ok = ::read(fd, &v, sizeof v) == static_cast<ssize_t>(sizeof v);
  ::close(fd);
  return ok ? v : -1;
}

/// Runs `cmd` (a shell line) and returns the smallest latency target seen
/// while it ran; *rc gets its exit status.
std::int32_t lowestWhile(const std::string& cmd, int* rc) {
  std::atomic<bool> done{false};
  std::thread t([&] {
    *rc = std::system(cmd.c_str());
    done.store(true);
  });
  std::int32_t lowest = cpuLatencyNow();
  while (!done.load()) {
    lowest = std::min(lowest, cpuLatencyNow());
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  t.join();
  return lowest;
}

TEST(HilCpuLatency, BothModesHoldTheRequestForTheirRunOnly) {
  const std::int32_t idle = cpuLatencyNow();
  if (idle < 0) GTEST_SKIP() << "/dev/cpu_dma_latency not readable here (root only)";
  if (idle <= 7) GTEST_SKIP() << "another process holds a CPU latency request of " << idle << " us";
  TempDir dir("cpu_latency");
  const std::string fw = "timeout 60 " + firmwareSim() + " " + scenePath("paper_ideal") +
                         " --lcm-url memq:// --rt-priority 0 ";
  const std::string log = " >" + dir / "fw.log" + " 2>&1";
  int rc = -1;

  EXPECT_EQ(lowestWhile(fw + "--duration 1 --cpu-dma-latency-us 7" + log, &rc), 7) << readFile(dir / "fw.log");
  EXPECT_EQ(rc, 0) << readFile(dir / "fw.log");
  EXPECT_EQ(readFile(dir / "fw.log").find("warning: cannot hold idle CPUs"), std::string::npos) << readFile(dir / "fw.log");
  EXPECT_NE(readFile(dir / "fw.log").find("firmware_sim: idle CPUs held to 7 us of wake-up latency"), std::string::npos)
      << readFile(dir / "fw.log");
  EXPECT_EQ(cpuLatencyNow(), idle) << "the request ends with the process";

  EXPECT_EQ(lowestWhile(fw + "--duration 1 --cpu-dma-latency-us -1" + log, &rc), idle) << readFile(dir / "fw.log");
  EXPECT_EQ(rc, 0) << readFile(dir / "fw.log");

  // Lockstep (no controller: it ends with the no-peer code after --start-timeout).
  EXPECT_EQ(lowestWhile(fw + "--lockstep --duration 1 --start-timeout 0.5 --cpu-dma-latency-us 9" + log, &rc), 9)
      << readFile(dir / "fw.log");
  EXPECT_EQ(WEXITSTATUS(rc), 6) << readFile(dir / "fw.log");
  EXPECT_EQ(readFile(dir / "fw.log").find("--cpu-dma-latency-us applies to real time only"), std::string::npos);
  EXPECT_EQ(cpuLatencyNow(), idle) << "the request ends with the process";
  EXPECT_EQ(lowestWhile(fw + "--lockstep --duration 1 --start-timeout 0.5 --cpu-dma-latency-us -1" + log, &rc), idle)
      << readFile(dir / "fw.log");
}

}  // namespace
}  // namespace gimbalsim::hil
