// Contact of the spatial clearance joint at the bearing's two ends
// (spatial_joint.hpp), against the definitions: journal pose from its five
// coordinates, velocities and generalised forces by finite differences of
// that pose (virtual work), and the planar joint's force for an untilted
// journal.
#include <gtest/gtest.h>

#include <random>

#include "gimbalsim/dynamics/spatial_joint.hpp"
#include "test_util.hpp"

namespace gimbalsim {
namespace {

/// The paper's bearing with every damping and friction off unless asked.
ContactParams bearing(FrictionLaw friction = FrictionLaw::None) {
  ContactParams c = test::model("paper_clearance", {"friction.law=none"}).bearing[1];
  c.friction = friction;
  return c;
}
constexpr double kLength = 0.05;  // [m]

/// Journal pose in B from the coordinates, written from the definition:
/// centre (p_x, p_y, 0), R_BJ = Rot(x, alpha) Rot(y, beta) Rot(z, theta).
struct Pose {
  Mat3 R;
  Vec3 p;
  Vec3 point(const Vec3& x_J) const { return p + R * x_J; }
};
Pose pose(const SpatialCoords& q) {
  const Mat3 R = (Eigen::AngleAxisd(q(2), Vec3::UnitX()) * Eigen::AngleAxisd(q(3), Vec3::UnitY()) *
                  Eigen::AngleAxisd(q(4), Vec3::UnitZ()))
                     .toRotationMatrix();
  return {R, Vec3(q(0), q(1), 0.0)};
}

TEST(SpatialJoint, CentredUntiltedJournalIsFreeAtBothEnds) {
  const ContactParams c = bearing();
  SpatialContact out;
  spatialContact(c, kLength, SpatialCoords::Zero(), SpatialCoords::Zero(), Vec3::Zero(), {0.0, 0.0}, out);
  for (const SpatialEnd& e : out.end) {
    EXPECT_EQ(e.delta, -c.clearance);
    EXPECT_EQ(e.fn, 0.0);
  }
  EXPECT_EQ(out.gamma, 0.0);
  EXPECT_TRUE(out.tau.isZero(0.0));
}

TEST(SpatialJoint, UntiltedJournalPressedEvenlyCarriesThePlanarForce) {
  // K / 2 at each end: an untilted journal carries K delta^n in all, the
  // planar joint's force, along -n, with no moment about its centre.
  const ContactParams c = bearing();
  const double delta = 2e-6;
  SpatialCoords q = SpatialCoords::Zero();
  q(0) = (c.clearance + delta) * 0.6;
  q(1) = -(c.clearance + delta) * 0.8;
  SpatialContact out;
  spatialContact(c, kLength, q, SpatialCoords::Zero(), Vec3::Zero(), {0.1, 0.1}, out);
  const double planar = normalForce(c, delta, 0.0, 0.1);
  ASSERT_GT(planar, 0.0);
  EXPECT_NEAR(out.end[0].fn + out.end[1].fn, planar, 1e-9 * planar);
  EXPECT_NEAR(out.end[0].fn, out.end[1].fn, 1e-12 * planar);
  EXPECT_NEAR(out.tau(0), -0.6 * planar, 1e-9 * planar);
  EXPECT_NEAR(out.tau(1), 0.8 * planar, 1e-9 * planar);
  for (int j = 2; j < 5; ++j) EXPECT_NEAR(out.tau(j), 0.0, 1e-12 * planar) << "coordinate " << j;
}

TEST(SpatialJoint, TiltAngleBetweenTheAxes) {
  const ContactParams c = bearing();
  SpatialCoords q = SpatialCoords::Zero();
  q(2) = 3e-3;
  q(3) = -4e-3;
  SpatialContact out;
  spatialContact(c, kLength, q, SpatialCoords::Zero(), Vec3::Zero(), {0.0, 0.0}, out);
  const Vec3 zJ = pose(q).R.col(2);
  EXPECT_NEAR(out.gamma, std::acos(zJ.z()), 1e-9);  // well conditioned at 5e-3 rad
  EXPECT_NEAR(out.gamma, 5e-3, 2e-8);
  // Tilted about x_B by alpha: the axis leaves the end planes at +-L/2 tan(alpha) along y.
  EXPECT_NEAR(out.end[1].e, 0.5 * kLength * std::hypot(std::tan(q(2)) / std::cos(q(3)), std::tan(q(3))), 1e-15);
}

/// A state touching at the +L/2 end only (tilted journal), random rates.
/// A random state with the journal 3 um into the bearing at its +L/2 end,
/// free at the -L/2 end, and the contact evaluated there.
struct Touching {
  SpatialCoords q, v;
  Vec3 omegaP;  ///< the bearing body's angular velocity [rad/s], bearing frame
  SpatialContact out;
};

Touching touching(std::mt19937& rng, const ContactParams& c) {
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  Touching t;
  // Tilt about x by alpha moves the +L/2 end by -L/2 tan(alpha) along y.
  t.q << 1e-5 * U(rng), -0.2 * c.clearance, 0.0, 1e-4 * U(rng), U(rng);
  t.q(2) = std::atan((0.8 * c.clearance + 3e-6) / (0.5 * kLength));
  for (int j = 0; j < 5; ++j) t.v(j) = (j < 2 ? 1e-2 : 0.5) * U(rng);
  t.omegaP = Vec3(U(rng), U(rng), U(rng));
  spatialContact(c, kLength, t.q, t.v, t.omegaP, {0.1, 0.1}, t.out);
  return t;
}

TEST(SpatialJoint, RelativeVelocityOfTheMaterialPoints) {
  // V = d/dt (journal point fixed in J) - d/dt (bearing point fixed in B),
  // the bearing body turning at omega_P: its points move by omega_P x X.
  std::mt19937 rng(3);
  const ContactParams c = bearing();
  for (int trial = 0; trial < 5; ++trial) {
    const auto [q, v, omegaP, out] = touching(rng, c);
    const SpatialEnd& e = out.end[1];
    ASSERT_GT(e.delta, 0.0);
    ASSERT_LT(out.end[0].delta, 0.0);
    const Pose P = pose(q);
    const Vec3 A = P.p + (0.5 * kLength / P.R(2, 2)) * P.R.col(2);  // axis meets the end plane
    const Vec3 QJ = A + c.journal_radius * e.n_B;
    const Vec3 QB = Vec3(0, 0, 0.5 * kLength) + c.bearing_radius * e.n_B;
    const Vec3 x_J = P.R.transpose() * (QJ - P.p);
    const double h = 1e-6;
    const Vec3 dJ = (pose(q + h * v).point(x_J) - pose(q - h * v).point(x_J)) / (2 * h);
    const Vec3 V = dJ + omegaP.cross(QJ) - omegaP.cross(QB);
    EXPECT_NEAR(e.vn, V.dot(e.n_B), 1e-8 * (V.norm() + 1e-3)) << "trial " << trial;
    EXPECT_LT((e.vt_B - (V - V.dot(e.n_B) * e.n_B)).norm(), 1e-8 * (V.norm() + 1e-3)) << "trial " << trial;
  }
}

TEST(SpatialJoint, GeneralisedForceIsTheVirtualWork) {
  // tau_j = sum_s F_s . dM_s/dq_j, M_s a point fixed in the journal (the
  // bearing's -F_s does no work on the joint's coordinates); with friction.
  std::mt19937 rng(5);
  const ContactParams c = bearing(FrictionLaw::Coulomb);
  for (int trial = 0; trial < 5; ++trial) {
    const auto [q, v, omegaP, out] = touching(rng, c);
    ASSERT_GT(out.end[1].fn, 0.0);
    ASSERT_GT(out.end[1].ft_B.norm(), 0.0);
    const Pose P = pose(q);
    SpatialCoords work = SpatialCoords::Zero();
    for (const SpatialEnd& e : out.end) {
      const Vec3 F = -e.fn * e.n_B + e.ft_B;
      const Vec3 x_J = P.R.transpose() * (e.M_B - P.p);
      for (int j = 0; j < 5; ++j) {
        const double h = 1e-7;
        const SpatialCoords dq = h * SpatialCoords::Unit(j);
        work(j) += F.dot((pose(q + dq).point(x_J) - pose(q - dq).point(x_J)) / (2 * h));
      }
    }
    EXPECT_LT((out.tau - work).norm(), 1e-6 * out.tau.norm()) << "contact: " << out.tau.transpose()
                                                              << "\nvirtual work: " << work.transpose();
  }
}

TEST(SpatialJoint, MotorCoupleLoadsTheTiltBySinBeta) {
  // Couple tau z_J on the journal: generalised force tau z_J . omega_j, omega_j
  // the journal's angular velocity per unit rate of coordinate j.
  const double tau = 2.5;
  SpatialCoords q;
  q << 1e-4, -2e-4, 0.3, -0.2, 0.7;
  const SpatialCoords g = spatialCoupleForce(tau, q(2), q(3));
  const Mat3 R = pose(q).R;
  for (int j = 0; j < 5; ++j) {
    const double h = 1e-6;
    const SpatialCoords dq = h * SpatialCoords::Unit(j);
    const Mat3 W = (pose(q + dq).R - pose(q - dq).R) / (2 * h) * R.transpose();  // [omega_j]x
    const Vec3 omega_j(W(2, 1), W(0, 2), W(1, 0));
    EXPECT_NEAR(g(j), tau * R.col(2).dot(omega_j), 1e-8) << "coordinate " << j;
  }
  EXPECT_NEAR(g(2), tau * std::sin(q(3)), 1e-15);
  EXPECT_NEAR(g(3), 0.0, 1e-15);  // beta: z_J is normal to Rot(x, alpha) y_B
}

}  // namespace
}  // namespace gimbalsim
