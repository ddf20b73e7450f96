#include "gimbalsim/controllers/attitude_estimator.hpp"

#include <algorithm>
#include <cmath>

namespace gimbalsim::controllers {
namespace {

int ringLength(const AttitudeEstimatorParams& p) noexcept {
  return std::clamp(p.history_length, 2, kAttitudeHistoryCapacity);
}

/// Ring entry k back from the newest (k = 0: newest).
const AttitudeHistoryEntry& back(const AttitudeEstimatorParams& p, const AttitudeEstimatorState& s,
                                 int k) noexcept {
  const int L = ringLength(p);
  return s.ring[static_cast<std::size_t>(((s.head - 1 - k) % L + L) % L)];
}

void record(const AttitudeEstimatorParams& p, AttitudeEstimatorState& s) noexcept {
  const int L = ringLength(p);
  s.ring[static_cast<std::size_t>(s.head)] = {s.t, s.q_WB};
  s.head = (s.head + 1) % L;
  s.count = std::min(s.count + 1, L);
}

/// The estimate at t_s <= s.t: slerp between the ring entries (or the ring's
/// newest and the current estimate) around it; false if t_s is older than the ring.
bool estimateAt(const AttitudeEstimatorParams& p, const AttitudeEstimatorState& s, double t_s,
                Quat& out) noexcept {
  Quat later = s.q_WB;
  double t_later = s.t;
  if (t_s >= t_later) {
    out = later;
    return true;
  }
  for (int k = 0; k < s.count; ++k) {
    const AttitudeHistoryEntry& e = back(p, s, k);
    if (e.t <= t_s) {
      const double u = t_later > e.t ? (t_s - e.t) / (t_later - e.t) : 0.0;
      out = e.q_WB.slerp(u, later);
      return true;
    }
    later = e.q_WB;
    t_later = e.t;
  }
  return false;
}

}  // namespace

const char* describe(SampleStatus s) noexcept {
  switch (s) {
    case SampleStatus::Initialized: return "initialized";
    case SampleStatus::Corrected: return "corrected";
    case SampleStatus::TooOld: return "too old (before the ring)";
    case SampleStatus::Future: return "stamped in the future";
    case SampleStatus::OutOfOrder: return "out of order";
  }
  return "?";
}

Quat expRotation(const Vec3& v) noexcept {
  const double a = v.norm();
  // sin(a/2)/a by its series below 1e-4 (error < a^4/3840 ~ 3e-20).
  const double k = a < 1e-4 ? 0.5 - a * a / 48.0 : std::sin(0.5 * a) / a;
  return Quat(std::cos(0.5 * a), k * v.x(), k * v.y(), k * v.z());
}

Vec3 logRotation(const Quat& q) noexcept {
  const double sgn = q.w() < 0.0 ? -1.0 : 1.0;
  const Vec3 u = sgn * q.vec();
  const double n = u.norm(), w = sgn * q.w();
  // angle = 2 atan2(n, w); 2 atan2(n, w) / n -> 2 / w as n -> 0.
  return (n > 1e-12 ? 2.0 * std::atan2(n, w) / n : 2.0 / w) * u;
}

double historySpan(const AttitudeEstimatorParams& p, double control_period) noexcept {
  // propagate() records once t - newest >= history_interval (1 - 1e-9): after this many whole periods.
  const double periods = std::max(1.0, std::ceil(p.history_interval * (1.0 - 1e-9) / control_period - 1e-9));
  return ringLength(p) * periods * control_period;
}

void propagate(const AttitudeEstimatorParams& p, AttitudeEstimatorState& s, double t,
               const Vec3& gyro_B) noexcept {
  s.omega_B = gyro_B - s.bias_B;
  if (s.count == 0) record(p, s);
  const double dt = t - s.t;
  if (!(dt > 0.0)) return;
  s.q_WB = (s.q_WB * expRotation(s.omega_B * dt)).normalized();
  s.t = t;
  if (t - back(p, s, 0).t >= p.history_interval * (1.0 - 1e-9)) record(p, s);
}

SampleStatus correct(const AttitudeEstimatorParams& p, AttitudeEstimatorState& s, double t_s,
                     const Quat& q_WB_meas) noexcept {
  SampleStatus status = SampleStatus::Corrected;
  Quat q_then;
  if (t_s > s.t + p.future_tol) {
    status = SampleStatus::Future;
  } else if (s.initialized && t_s <= s.t_last_sample) {
    status = SampleStatus::OutOfOrder;
  } else if (!estimateAt(p, s, t_s, q_then)) {
    status = SampleStatus::TooOld;
  }
  if (status != SampleStatus::Corrected) {
    ++s.samples_rejected;
    return status;
  }
  const Vec3 e_B = logRotation(q_then.conjugate() * q_WB_meas.normalized());
  double gain = 1.0;
  if (s.initialized) {
    const double dt_s = std::min(t_s - s.t_last_sample, p.max_gain_interval);
    gain = std::min(1.0, p.k_p * dt_s);
    s.bias_B = (s.bias_B - p.k_i * dt_s * e_B).cwiseMax(-p.max_bias).cwiseMin(p.max_bias);
  } else {
    status = SampleStatus::Initialized;
    s.initialized = true;
  }
  const Quat C = expRotation(gain * (q_then * e_B));  // q_then * v rotates v into W
  s.q_WB = (C * s.q_WB).normalized();
  // The ring fills slots 0, 1, ... before it wraps: the held entries are the first count.
  for (int i = 0; i < s.count; ++i) {
    Quat& q = s.ring[static_cast<std::size_t>(i)].q_WB;
    q = (C * q).normalized();
  }
  s.t_last_sample = t_s;
  ++s.samples_used;
  return status;
}

}  // namespace gimbalsim::controllers
