// Single-producer single-consumer ring of fixed capacity: the hand-over
// between the real-time thread and the communication thread. Lock-free and
// wait-free on both sides (push fails when full, pop fails when empty);
// storage allocated once at construction.
#pragma once

#include <atomic>
#include <cstddef>
#include <memory>

namespace gimbalsim::firmware {

template <class T>
class SpscRing {
 public:
  /// capacity is rounded up to a power of two.
  explicit SpscRing(std::size_t capacity) {
    std::size_t n = 1;
    while (n < capacity) n <<= 1;
    mask_ = n - 1;
    items_ = std::make_unique<T[]>(n);
  }

  /// Producer only. False (and nothing written) when the ring is full.
  bool push(const T& x) noexcept {
    const std::size_t h = head_.load(std::memory_order_relaxed);
    if (h - tail_.load(std::memory_order_acquire) > mask_) return false;
    items_[h & mask_] = x;
    head_.store(h + 1, std::memory_order_release);
    return true;
  }

  /// Consumer only. False when empty.
  bool pop(T& out) noexcept {
    const std::size_t t = tail_.load(std::memory_order_relaxed);
    if (t == head_.load(std::memory_order_acquire)) return false;
    out = items_[t & mask_];
    tail_.store(t + 1, std::memory_order_release);
    return true;
  }

  std::size_t capacity() const noexcept { return mask_ + 1; }

 private:
  std::size_t mask_ = 0;
  std::unique_ptr<T[]> items_;
  alignas(64) std::atomic<std::size_t> head_{0};  ///< next slot the producer writes
  alignas(64) std::atomic<std::size_t> tail_{0};  ///< next slot the consumer reads
};

}  // namespace gimbalsim::firmware
