#include "gimbalsim/controllers/tracker_fusion.hpp"

#include <algorithm>
#include <cmath>

#include "gimbalsim/pointing/tracker_axes.hpp"

namespace gimbalsim::controllers {

namespace {
/// [rad] a reading beyond this is no small-angle pointing error: refused.
constexpr double kMaxReading = 0.5;
/// [-] the azimuth's lever on the tracker's axes below this: the keyhole.
constexpr double kKeyholeLever = 0.05;
}  // namespace

void noteAntennaReading(TrackerFusionState& s, const contract::Antenna& a) noexcept {
  const Vec3 w(a.gyro_rate[0], a.gyro_rate[1], a.gyro_rate[2]);
  if (w.allFinite() && a.seq >= 0) {
    s.gyro_seq = a.seq;
    s.gyro_rate = w;
  }
  if (a.tracker_valid == 0 || a.tracker_outage != 0) return;
  const Vec2 r(a.tracker_error[0], a.tracker_error[1]);
  if (!std::isfinite(a.tracker_time) || a.tracker_time < 0.0 || !r.allFinite() || r.cwiseAbs().maxCoeff() > kMaxReading) {
    ++s.rejected;
    return;
  }
  s.pending = true;
  s.pending_time = a.tracker_time;
  s.pending_reading = r;
}

namespace {
/// Joint corrections from a rotation's (u, v) components (see trackerJointError).
Vec2 jointFromUV(const pointing::TrackerAxes& ax, const Vec3& k1_B, const Vec3& k2_S1, double theta2,
                 const Vec2& reading) noexcept {
  // The azimuth axis in the antenna frame (k1 is the same in the base and
  // shaft 1 frames); the elevation axis is k2_S1 there.
  const Vec3 k1_A = Eigen::AngleAxisd(-theta2, k2_S1) * k1_B;
  Eigen::Matrix2d m;
  m << ax.u.dot(k1_A), ax.u.dot(k2_S1), ax.v.dot(k1_A), ax.v.dot(k2_S1);
  if (!(std::fabs(m(0, 1)) > 1e-6)) return Vec2::Zero();  // u.k2 = |k2 x b|: the configuration keeps it > 1e-6
  if (std::fabs(m(1, 0)) < kKeyholeLever) return {0.0, reading(0) / m(0, 1)};
  return m.inverse() * reading;
}
}  // namespace

Vec2 trackerJointError(const Vec3& k1_B, const Vec3& k2_S1, const Vec3& boresight_S2, double theta2,
                       const Vec2& reading) noexcept {
  return jointFromUV(pointing::trackerAxes(k2_S1, boresight_S2), k1_B, k2_S1, theta2, reading);
}

bool loadRate(const TrackerFusionParams& p, const Vec3& k1_B, const Vec3& k2_S1, const Vec3& boresight_S2,
              const TrackerFusionState& s, std::int64_t k, const Vec2& theta, const Vec3& omega_B, Vec2& rate) noexcept {
  if (!p.use_tracker || s.gyro_seq != k || !omega_B.allFinite()) return false;
  const Mat3 R_BA = (Eigen::AngleAxisd(theta(0), k1_B) * Eigen::AngleAxisd(theta(1), k2_S1)).toRotationMatrix();
  const Vec3 w_rel_A = s.gyro_rate - R_BA.transpose() * omega_B;
  const pointing::TrackerAxes ax = pointing::trackerAxes(k2_S1, boresight_S2);
  rate = jointFromUV(ax, k1_B, k2_S1, theta(1), Vec2(w_rel_A.dot(ax.u), w_rel_A.dot(ax.v)));
  return true;
}

Vec2 loadOffset(const TrackerFusionParams& p, const Vec3& k1_B, const Vec3& k2_S1, const Vec3& boresight_S2,
                TrackerFusionState& s, std::int64_t k, double period, const Vec2& lead, double theta2) noexcept {
  if (!p.use_tracker || k < 0) return Vec2::Zero();
  const int slot = static_cast<int>(k % TrackerFusionState::kSize);
  s.seq[slot] = k;
  s.lead[slot] = lead;
  s.theta2[slot] = theta2;
  if (s.pending) {
    s.pending = false;
    const double ks = std::round(s.pending_time / period);
    const std::int64_t k_s = ks >= 0.0 && ks <= static_cast<double>(k) ? static_cast<std::int64_t>(ks) : -1;
    const int i = static_cast<int>((k_s >= 0 ? k_s : 0) % TrackerFusionState::kSize);
    if (k_s >= 0 && s.seq[i] == k_s) {
      // At the sample's tick the antenna lacked dtheta of its target; a rigid
      // chain would have lacked lead: the rest is the play's offset.
      s.offset_measured = s.lead[i] - trackerJointError(k1_B, k2_S1, boresight_S2, s.theta2[i], s.pending_reading);
      if (s.used_tick < 0 || k - s.used_tick > kRelockTicks) s.locked = false;  // acquire (again)
      s.measured = true;
      s.used_tick = k;
      ++s.used;
    } else {
      ++s.rejected;  // a sample time this controller never ticked at (or older than its history)
    }
  }
  if (s.locked) {
    s.offset = s.offset_measured;
  } else if (s.measured) {
    const double step = p.offset_rate * period;
    const Vec2 gap = s.offset_measured - s.offset;
    s.locked = gap.cwiseAbs().maxCoeff() <= step;
    for (int i = 0; i < 2; ++i) s.offset(i) += std::clamp(gap(i), -step, step);
  }
  return s.offset;
}

}  // namespace gimbalsim::controllers
