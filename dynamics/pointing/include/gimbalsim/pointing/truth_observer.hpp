// The truth pointing error: an observer outside the plant. It compares the
// boresight the plant reports (truth message) with the target line of sight
// of the profile at the same time, so firmware_sim and the in-process closed
// loop measure pointing the same way, and the plant itself knows no target.
#pragma once

#include <cmath>

#include "gimbalsim/dynamics/model.hpp"
#include "gimbalsim/pointing/target_profile.hpp"

namespace gimbalsim::pointing {

class TruthObserver {
 public:
  /// profile may be null: the target is then initial_boresight (where the
  /// antenna pointed at t = 0, unit, inertial). m and profile must outlive it.
  TruthObserver(const Model& m, const TargetProfile* profile, const Vec3& initial_boresight)
      : m_(m), profile_(profile), initial_(initial_boresight) {}

  /// The target line of sight at t [s] (unit, inertial) into target[3], and
  /// the angle [rad] between boresight[3] and it. noexcept, no allocation.
  double observe(double t, const double boresight[3], double target[3]) const noexcept {
    const Vec3 d = lineOfSight(t);
    target[0] = d.x(), target[1] = d.y(), target[2] = d.z();
    return pointingError(Vec3(boresight[0], boresight[1], boresight[2]), d);
  }

  /// The target's line of sight at t [s] (unit, inertial).
  Vec3 lineOfSight(double t) const noexcept {
    if (profile_ == nullptr) return initial_;
    const ProfileSample ps = profile_->at(t);
    return losBoresight(m_, ps.q(0), ps.q(1));
  }

  /// The profile at t (the target's joint angles and its segment); a
  /// default sample (segment Wait) without a profile.
  ProfileSample sample(double t) const noexcept { return profile_ != nullptr ? profile_->at(t) : ProfileSample{}; }

 private:
  const Model& m_;
  const TargetProfile* profile_;
  Vec3 initial_;
};

/// The knowledge error of an attitude estimate: the angle [rad] of the
/// rotation from q_true to q_est (both base -> inertial), in [0, pi].
inline double attitudeError(const Quat& q_true, const Quat& q_est) noexcept {
  const Quat q = q_true.conjugate() * q_est;
  const double sgn = q.w() < 0.0 ? -1.0 : 1.0;
  const Vec3 u = sgn * q.vec();
  const double n = u.norm(), w = sgn * q.w();
  return ((n > 1e-12 ? 2.0 * std::atan2(n, w) / n : 2.0 / w) * u).norm();  // |log(q)|, as the estimator's
}

}  // namespace gimbalsim::pointing
