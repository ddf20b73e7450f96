// When a sensor with its own rate and latency (the star tracker, the
// boresight tracker) takes and delivers its samples on the control ticks.
// One schedule for both, so they agree to the tick. noexcept, no allocation.
//
// Tick k at t_k = k T. Sample j belongs to the instant j P (P = 1 / rate) and
// is taken in the first tick at or after it (at most one per tick). It is
// delivered in the first tick at or after t_s + latency; when several fall due
// in one tick the newest is delivered and the older ones are dropped. In an
// outage no sample is taken and those due are dropped.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace gimbalsim::firmware {

/// N: the doubles a sample carries (a quaternion: 4; a tracker reading: 2).
/// kMaxLatencyPeriods: the longest latency, in sample periods, the caller's
/// key check allows (it sizes the fixed queue of samples in flight).
template <int N, int kMaxLatencyPeriods>
class SampleSchedule {
 public:
  struct Sample {
    std::int64_t deliver_tick = 0;
    double t = -1.0;  ///< [s] sample time; -1: none
    double value[N] = {};
  };

  /// rate > 0 and latency < kMaxLatencyPeriods / rate (checked by the caller's
  /// keys); T > 0 the control period. Others only keep the arithmetic defined.
  SampleSchedule(double rate, double latency, double T, const Sample& initial) noexcept
      : P_(rate > 0.0 ? 1.0 / rate : T), T_(T > 0.0 ? T : 1.0), latency_ticks_(ticksAtOrAfter(latency)),
        last_(initial) {}

  /// Whether tick k takes a sample.
  bool takes(std::int64_t k) const noexcept { return k >= next_tick_; }

  /// Tick k's turn: if it takes a sample, value (the caller's reading at t_k)
  /// is queued unless in an outage, and the next sample's tick is found.
  template <class Read>
  void take(std::int64_t k, bool outage, Read&& read) noexcept {
    if (k < next_tick_) return;
    if (!outage) queue(k, read);
    advanceSampleIndex(k);
  }

  /// The newest sample due at tick k, or null (none due, or an outage: then
  /// those due are dropped). The one delivered becomes last().
  const Sample* deliver(std::int64_t k, bool outage) noexcept {
    const Sample* due = nullptr;
    while (count_ > 0 && ring_[head_].deliver_tick <= k) {
      due = &ring_[head_];
      head_ = (head_ + 1) % kCapacity;
      --count_;
    }
    if (due == nullptr || outage) return nullptr;
    last_ = *due;
    return &last_;
  }

  /// The last sample delivered (the initial one before any).
  const Sample& last() const noexcept { return last_; }

 private:
  /// Latency < kMaxLatencyPeriods periods and samples at least max(P - T, T)
  /// apart keep fewer than this queued.
  static constexpr int kCapacity = 4 * kMaxLatencyPeriods;
  static constexpr int kMaxIndexSteps = 4;  ///< floor(t / P) is off by at most one or two in rounding

  /// Ticks from 0 to the first tick at or after time x [s].
  std::int64_t ticksAtOrAfter(double x) const noexcept {
    const double k = std::ceil(x / T_ - 1e-9);
    return k < 4e18 ? static_cast<std::int64_t>(k) : std::int64_t{4000000000000000000};
  }

  template <class Read>
  void queue(std::int64_t k, Read& read) noexcept {
    if (count_ == kCapacity) {  // cannot happen within the latency limit; keep the newest
      head_ = (head_ + 1) % kCapacity;
      --count_;
    }
    Sample& s = ring_[(head_ + count_) % kCapacity];
    s.deliver_tick = k + latency_ticks_;
    s.t = static_cast<double>(k) * T_;
    read(s.value);
    ++count_;
  }

  /// The next sample index j whose tick is after k. The index jumps straight
  /// to the first instant after t_k (no count one by one: at a rate far above
  /// the control rate that would be ~rate x T steps per tick), clamped below
  /// int64's end; the loop then only steps over rounding, a bounded few times.
  void advanceSampleIndex(std::int64_t k) noexcept {
    const double t = static_cast<double>(k) * T_;
    const double j = std::min(std::floor(t / P_), 4e18);
    next_j_ = std::max(next_j_ + 1, static_cast<std::int64_t>(j));
    for (int i = 0; i < kMaxIndexSteps && (next_tick_ = ticksAtOrAfter(static_cast<double>(next_j_) * P_)) <= k;
         ++i) {
      ++next_j_;
    }
    if (next_tick_ <= k) next_tick_ = k + 1;  // P below double's resolution at t: one sample per tick
  }

  double P_, T_;
  std::int64_t latency_ticks_;
  std::int64_t next_j_ = 0;     ///< index of the next sample
  std::int64_t next_tick_ = 0;  ///< the tick that takes it
  Sample ring_[kCapacity];
  Sample last_;
  int head_ = 0, count_ = 0;
};

}  // namespace gimbalsim::firmware
