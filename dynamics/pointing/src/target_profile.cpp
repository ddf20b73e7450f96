#include "gimbalsim/pointing/target_profile.hpp"

#include <Eigen/Geometry>

namespace gimbalsim::pointing {

const char* describe(Segment s) {
  switch (s) {
    case Segment::Wait: return "wait";
    case Segment::Slew: return "slew";
    case Segment::Hold: return "hold";
    case Segment::Track: return "track";
  }
  return "?";
}

ProfileSample TargetProfile::at(double t) const noexcept {
  ProfileSample p;
  if (t < slew_start) {
    p.q = start;
    p.segment = Segment::Wait;
    return p;
  }
  if (t < slewEnd()) {
    // Minimum-jerk quintic (Flash & Hogan 1985): s = 10u^3 - 15u^4 + 6u^5.
    const double T = slew_time, u = (t - slew_start) / T;
    const double u2 = u * u, u3 = u2 * u;
    const double s = u3 * (10.0 - 15.0 * u + 6.0 * u2);
    const double ds = 30.0 * u2 * (1.0 - 2.0 * u + u2) / T;    // 30 u^2 (1-u)^2 / T
    const double dds = 60.0 * u * (1.0 - 3.0 * u + 2.0 * u2) / (T * T);  // 60 u (1-u)(1-2u) / T^2
    const Vec2 d = slew_target - start;
    p.q = start + s * d;
    p.dq = ds * d;
    p.ddq = dds * d;
    p.segment = Segment::Slew;
    return p;
  }
  if (t < trackStart()) {
    p.q = slew_target;
    p.segment = Segment::Hold;
    return p;
  }
  const double tau = t - trackStart(), Tr = track_ramp_time;
  const double e = std::exp(-tau / Tr);
  p.segment = Segment::Track;
  for (int i = 0; i < 2; ++i) {
    const double r = track_rate(i), A = track_amplitude(i), w = 2.0 * M_PI / track_period(i);
    // -expm1 keeps 1 - exp(-x) exact for small x.
    p.q(i) = slew_target(i) + r * (tau + Tr * std::expm1(-tau / Tr)) + A * (1.0 - std::cos(w * tau));
    p.dq(i) = r * (-std::expm1(-tau / Tr)) + A * w * std::sin(w * tau);
    p.ddq(i) = r * e / Tr + A * w * w * std::cos(w * tau);
  }
  return p;
}

Vec3 losBoresight(const Model& m, double az, double el) noexcept {
  return gimbalBoresight(m.k1_B, m.k2_S1, m.boresight_S2, az, el);
}

Vec3 gimbalBoresight(const Vec3& k1_B, const Vec3& k2_S1, const Vec3& b_S2, double az, double el) noexcept {
  const Eigen::AngleAxisd R1(az, k1_B.normalized()), R2(el, k2_S1.normalized());
  return (R1 * (R2 * b_S2)).normalized();
}

}  // namespace gimbalsim::pointing
