// Fixed latency histogram for the real-time loop: 1 us bins up to a fixed
// range plus one overflow bin, exact max. Written by one thread (the RT loop)
// and read by another (statistics): counts are relaxed atomics, so a reader
// sees a slightly stale but never torn histogram. No allocation after
// construction.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>

namespace gimbalsim::firmware {

class Histogram {
 public:
  /// bins of 1 us covering [0, range_us); values >= range_us go to the overflow bin.
  explicit Histogram(int range_us = 10000)
      : range_(range_us), bins_(std::make_unique<std::atomic<std::uint64_t>[]>(range_us + 1)) {
    for (int i = 0; i <= range_; ++i) bins_[i].store(0, std::memory_order_relaxed);
  }

  /// Single writer. Negative values count in bin 0.
  void add(double us) noexcept {
    const int b = us <= 0.0 ? 0 : (us >= range_ ? range_ : static_cast<int>(us));
    bins_[b].store(bins_[b].load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
    count_.store(count_.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
    if (us > max_.load(std::memory_order_relaxed)) max_.store(us, std::memory_order_relaxed);
  }

  std::uint64_t count() const noexcept { return count_.load(std::memory_order_relaxed); }
  double max() const noexcept { return max_.load(std::memory_order_relaxed); }
  int range() const noexcept { return range_; }

  /// Value below which a fraction p of the samples lie [us], resolved to the
  /// bin's upper edge (the exact max for the overflow bin); 0 when empty.
  double quantile(double p) const noexcept {
    std::uint64_t n = 0;
    for (int i = 0; i <= range_; ++i) n += bins_[i].load(std::memory_order_relaxed);
    if (n == 0) return 0.0;
    // Rank of the quantile, 1-based: the smallest r with r >= p n.
    const double want = std::max(1.0, p * static_cast<double>(n));
    std::uint64_t acc = 0;
    for (int i = 0; i < range_; ++i) {
      acc += bins_[i].load(std::memory_order_relaxed);
      if (static_cast<double>(acc) >= want) return std::min(static_cast<double>(i + 1), max());
    }
    return max();
  }

 private:
  int range_;
  std::unique_ptr<std::atomic<std::uint64_t>[]> bins_;
  std::atomic<std::uint64_t> count_{0};
  std::atomic<double> max_{0.0};
};

}  // namespace gimbalsim::firmware
