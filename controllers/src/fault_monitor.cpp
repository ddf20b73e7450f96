#include "gimbalsim/controllers/fault_monitor.hpp"

#include <cmath>
#include <limits>

namespace gimbalsim::controllers {

namespace {
/// a - b saturated to the int64 range: seqs come from the network and may be anything.
std::int64_t satSub(std::int64_t a, std::int64_t b) noexcept {
  std::int64_t r;
  if (!__builtin_sub_overflow(a, b, &r)) return r;
  return b < 0 ? std::numeric_limits<std::int64_t>::max() : std::numeric_limits<std::int64_t>::min();
}
/// a + b for counts (both >= 0), saturated.
long long satAdd(long long a, long long b) noexcept {
  long long r;
  return __builtin_add_overflow(a, b, &r) ? std::numeric_limits<long long>::max() : r;
}
}  // namespace

MonitorFlags observeStatus(const MonitorConfig& c, MonitorState& s, double period, std::int64_t seq,
                           const double angle[2], const double rate[2], std::int64_t attitude_seq,
                           bool star_outage) noexcept {
  MonitorFlags f;
  f.star_outage = star_outage;
  f.age = attitude_seq > seq ? satSub(attitude_seq, seq) : 0;
  f.stale = f.age >= c.stale_ticks;
  s.stale_run = f.stale ? s.stale_run + 1 : 0;
  if (f.stale) ++s.stale_statuses;
  f.safe = s.stale_run > c.hold_ticks;
  if (f.safe) ++s.safe_statuses;

  // Encoder against rate, over windows of consecutive statuses (a gap restarts the window).
  const std::int64_t step = s.last_seq >= 0 ? satSub(seq, s.last_seq) : 0;
  const bool consecutive = s.last_seq >= 0 && step == 1;
  if (s.last_seq >= 0 && step > 1) s.missing_statuses = satAdd(s.missing_statuses, step - 1);
  if (!consecutive || s.window_n == 0) {
    for (int i = 0; i < 2; ++i) {
      s.window_theta0[i] = angle[i];
      s.window_rate_int[i] = 0.0;
    }
    s.window_n = 0;
  } else {
    for (int i = 0; i < 2; ++i) s.window_rate_int[i] += 0.5 * (s.prev_rate[i] + rate[i]) * period;  // trapezoid
  }
  if (consecutive) ++s.window_n;
  if (s.window_n >= c.stuck_window) {
    for (int i = 0; i < 2; ++i) {
      const double moved = angle[i] - s.window_theta0[i];
      const bool disagree = std::fabs(moved - s.window_rate_int[i]) > c.stuck_tol;
      if (disagree && !s.suspect[i]) ++s.suspect_onsets[i];
      if (disagree) s.suspect[i] = true;
      else if (std::fabs(moved) > c.stuck_tol) s.suspect[i] = false;  // moving with the rate again
      s.window_theta0[i] = angle[i];
      s.window_rate_int[i] = 0.0;
    }
    s.window_n = 0;  // the next window starts from this status
  }
  for (int i = 0; i < 2; ++i) {
    s.prev_rate[i] = rate[i];
    f.encoder_suspect[i] = s.suspect[i];
  }
  s.last_seq = seq;
  return f;
}

}  // namespace gimbalsim::controllers
