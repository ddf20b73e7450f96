// Statistics of firmware_sim's loop: written by the loop thread without
// allocation, read by the communication thread (published on
// GIMBAL_LOOP_STATS) and by the exit summary.
#pragma once

#include <atomic>
#include <cstdint>

#include "gimbalsim/firmware_sim/histogram.hpp"

namespace gimbalsim::firmware {

struct LoopStats {
  Histogram period{10000}, lateness{10000}, compute{10000};  // [us], 1 us bins to 10 ms
  /// Each tick's compute in the loop thread's CPU time (CLOCK_THREAD_CPUTIME_ID),
  /// the same span as `compute` (wall): preemption does not inflate it [us],
  /// 1 us bins to 10 ms.
  Histogram compute_cpu{10000};
  /// Of that span, the stepping alone (the plant's steps of the tick): the
  /// work the worst-case tick bound bounds [us], 1 us bins to 10 ms.
  Histogram stepping_cpu{10000};
  /// The tick with the longest stepping, and its RK4 sub-steps (read at exit).
  std::atomic<std::int64_t> stepping_cpu_max_tick{-1};
  std::atomic<int> stepping_cpu_max_substeps{0};
  /// Real time: ticks run after their deadline had passed (catching up with
  /// wall-clock time after an overrun), and by how much, in units of 10 us
  /// (10 us bins to 1 s, exact max): add(late_us / 10), quantile() * 10.
  Histogram late{100000};
  std::atomic<std::int64_t> late_ticks{0};
  std::atomic<std::int64_t> ticks{0}, overruns{0}, substeps{0}, dropped_out{0};
  std::atomic<int> substeps_max{0};

  /// Loop thread, once per tick: its compute and its stepping in CPU time [us].
  void addComputeCpu(std::int64_t tick, double cpu_us, double stepping_us, int substeps_in_tick) noexcept {
    if (stepping_us > stepping_cpu.max()) {
      stepping_cpu_max_tick.store(tick, std::memory_order_relaxed);
      stepping_cpu_max_substeps.store(substeps_in_tick, std::memory_order_relaxed);
    }
    compute_cpu.add(cpu_us);
    stepping_cpu.add(stepping_us);
  }

  /// Loop thread, once per tick.
  void addTick(std::int64_t ticks_done, int substeps_in_tick) noexcept {
    substeps.store(substeps.load(std::memory_order_relaxed) + substeps_in_tick, std::memory_order_relaxed);
    if (substeps_in_tick > substeps_max.load(std::memory_order_relaxed)) {
      substeps_max.store(substeps_in_tick, std::memory_order_relaxed);
    }
    ticks.store(ticks_done, std::memory_order_relaxed);
  }

  /// RK4 evaluations per tick, mean over the ticks so far.
  double substepsMean() const noexcept {
    const std::int64_t t = ticks.load();
    return t > 0 ? static_cast<double>(substeps.load()) / static_cast<double>(t) : 0.0;
  }
};

}  // namespace gimbalsim::firmware
