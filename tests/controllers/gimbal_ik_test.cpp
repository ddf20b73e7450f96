// Gimbal inverse kinematics (gimbal_ik.hpp): the boresight the dynamics'
// own kinematics produce at known joint angles gives those angles back (and
// their branch); the joint rates match a finite difference of the angles; the
// base-rate feed-forward matches a finite difference of R_WB(t)^T d_W(t); the
// curvature and the joint accelerations (base angular acceleration included)
// match second differences; a tilted joint-2 axis converges by Gauss-Newton;
// the keyhole keeps the azimuth.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "gimbalsim/controllers/gimbal_ik.hpp"
#include "test_util.hpp"

namespace gimbalsim::controllers {
namespace {

constexpr double kAngleTol = 1e-12;  // [rad]

/// A random unit quaternion (w x y z).
Quat randomAttitude(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Quat(n(rng), n(rng), n(rng), n(rng)).normalized();
}

/// Joint angles away from the keyhole (|cos theta2| >= 0.15), either branch.
Vec2 randomAngles(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-M_PI, M_PI);
  Vec2 th{u(rng), u(rng)};
  while (std::abs(std::cos(th(1))) < 0.15) th(1) = u(rng);
  return th;
}

/// Boresight in the base frame of a state of variant V at angles th and base
/// attitude q_WB, from the dynamics' kinematics (observables.hpp boresight()).
template <class V>
Vec3 dynamicsBoresightB(const Model& m, const Vec2& th, const Quat& q_WB, double ecc = 0.0) {
  State<V> s;
  constexpr int QJ = State<V>::QJ;
  s.q(3) = q_WB.w(), s.q(4) = q_WB.x(), s.q(5) = q_WB.y(), s.q(6) = q_WB.z();
  s.q(QJ) = th(0);
  s.q(QJ + V::NJ - 1) = th(1);
  if constexpr (V::kContact) s.q(QJ + 1) = ecc, s.q(QJ + 2) = -0.5 * ecc;
  return q_WB.toRotationMatrix().transpose() * test::boresightOf(m, s);
}

template <class V>
void checkRoundTrip(const Model& m, std::uint64_t seed) {
  const GimbalGeometry g = gimbalGeometry(m);
  ASSERT_TRUE(g.closed_form);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  std::uniform_int_distribution<int> turns(-3, 3);
  int over = 0;
  for (int k = 0; k < 2000; ++k) {
    const Vec2 truth = randomAngles(rng);
    const Vec3 d_B = dynamicsBoresightB<V>(m, truth, randomAttitude(rng), 1e-4);
    // A previous solution near the truth, on another 2 pi representative.
    const Vec2 wrap = 2.0 * M_PI * Vec2(turns(rng), turns(rng));
    const Vec2 prev = truth + wrap + Vec2(jitter(rng), jitter(rng));
    const IkSolution s = solveAngles(g, d_B, prev);
    EXPECT_NEAR(s.theta(0), truth(0) + wrap(0), kAngleTol) << "case " << k;
    EXPECT_NEAR(s.theta(1), truth(1) + wrap(1), kAngleTol) << "case " << k;
    EXPECT_EQ(s.over_the_top, std::cos(truth(1)) < 0.0) << "case " << k;
    EXPECT_FALSE(s.singular);
    EXPECT_LT(s.residual, 1e-14);
    over += s.over_the_top;
  }
  EXPECT_GT(over, 500);  // both branches exercised
}

TEST(GimbalIk, DynamicsBoresightGivesItsAnglesBackIdeal) {
  checkRoundTrip<FloatingIdeal>(test::model("paper_ideal"), 1);
}

TEST(GimbalIk, DynamicsBoresightGivesItsAnglesBackClearance) {
  // The eccentricity moves the antenna but does not turn it.
  checkRoundTrip<FloatingClearance>(test::model("paper_clearance"), 2);
}

TEST(GimbalIk, LosBoresightOfTheInitialPoseGivesItsAnglesBack) {
  const Model m = test::model("paper_ideal");
  const GimbalGeometry g = gimbalGeometry(m);
  for (const Vec2& truth : {Vec2(0.5, 0.3), Vec2(-2.0, 1.2), Vec2(3.0, -0.9), Vec2(0.1, 2.5)}) {
    const IkSolution s = solveAngles(g, pointing::losBoresight(m, truth(0), truth(1)), truth + Vec2(0.2, -0.2));
    EXPECT_NEAR((s.theta - truth).cwiseAbs().maxCoeff(), 0.0, kAngleTol);
    EXPECT_LT(pointing::pointingError(boresightB(g, s.theta), pointing::losBoresight(m, truth(0), truth(1))),
              1e-15);
  }
}

TEST(GimbalIk, PreviousSolutionPicksTheBranch) {
  const GimbalGeometry g = gimbalGeometry(test::model("paper_ideal"));
  const Vec2 truth{0.4, 0.6};
  const Vec3 d = boresightB(g, truth);
  const Vec2 other{truth(0) + M_PI, M_PI - truth(1)};  // the same boresight over the top
  EXPECT_LT(pointing::pointingError(boresightB(g, other), d), 1e-15);
  const IkSolution a = solveAngles(g, d, truth + Vec2(0.1, 0.1));
  const IkSolution b = solveAngles(g, d, other + Vec2(0.1, 0.1));
  EXPECT_FALSE(a.over_the_top);
  EXPECT_TRUE(b.over_the_top);
  EXPECT_NEAR((a.theta - truth).norm(), 0.0, kAngleTol);
  EXPECT_NEAR((b.theta - other).norm(), 0.0, kAngleTol);
}

/// A direction turning about a fixed axis: d(t) = Rot(a, w t) d0, dd = w a x d.
struct TurningDirection {
  Vec3 a = Vec3(0.3, -0.5, 0.8).normalized();
  double w = 0.7;  // [rad/s]
  Vec3 d0 = Vec3(0.6, 0.2, -0.3).normalized();
  Vec3 at(double t) const { return axisAngle(a, w * t) * d0; }
  Vec3 rate(double t) const { return w * a.cross(at(t)); }
};

TEST(GimbalIk, RatesMatchAFiniteDifferenceOfTheAngles) {
  const GimbalGeometry g = gimbalGeometry(test::model("paper_ideal"));
  const TurningDirection dir;
  Vec2 prev = solveAngles(g, dir.at(0.0), Vec2::Zero()).theta;
  const double h = 1e-5;
  for (double t = 0.0; t < 8.0; t += 0.05) {
    const IkSolution s = solveAngles(g, dir.at(t), prev);
    ASSERT_FALSE(s.singular);
    const Vec2 fd = (solveAngles(g, dir.at(t + h), s.theta).theta - solveAngles(g, dir.at(t - h), s.theta).theta) /
                    (2.0 * h);
    const Vec2 rate = solveRates(g, s.theta, dir.rate(t));
    EXPECT_LT((rate - fd).cwiseAbs().maxCoeff(), 1e-8 * (1.0 + fd.cwiseAbs().maxCoeff())) << "t = " << t;
    EXPECT_LT((prev - s.theta).cwiseAbs().maxCoeff(), 0.2) << "continuous, t = " << t;
    prev = s.theta;
  }
}

/// R_WB(t) = Rz(a t) Rx(b t): omega_B = Rx(b t)^T (0, 0, a) + (b, 0, 0).
struct RotatingBase {
  Quat q0 = Quat(0.9, 0.1, -0.3, 0.2).normalized();
  double a = 0.05, b = -0.03;  // [rad/s]
  Mat3 R(double t) const {
    return q0.toRotationMatrix() * axisAngle(Vec3::UnitZ(), a * t) * axisAngle(Vec3::UnitX(), b * t);
  }
  Vec3 omega(double t) const {
    return axisAngle(Vec3::UnitX(), b * t).transpose() * Vec3(0.0, 0.0, a) + Vec3(b, 0.0, 0.0);
  }
};

TEST(GimbalIk, BaseRateFeedForwardMatchesAFiniteDifference) {
  const RotatingBase base;
  const TurningDirection dir;
  const double h = 1e-5;
  for (double t = 0.0; t < 20.0; t += 0.5) {
    const LosInBase l = losInBase(dir.at(t), dir.rate(t), base.R(t), base.omega(t));
    const Vec3 fd =
        (base.R(t + h).transpose() * dir.at(t + h) - base.R(t - h).transpose() * dir.at(t - h)) / (2.0 * h);
    EXPECT_LT((l.d_B - base.R(t).transpose() * dir.at(t)).norm(), 1e-15);
    EXPECT_LT((l.d_B_dot - fd).norm(), 1e-9) << "t = " << t;
  }
}

TEST(GimbalIk, JointRatesOfAnInertialTargetFromARotatingBase) {
  // The whole feed-forward: inertial target and base rotation -> joint rates.
  const GimbalGeometry g = gimbalGeometry(test::model("paper_ideal"));
  const RotatingBase base;
  const TurningDirection dir;
  auto angles = [&](double t, const Vec2& prev) {
    return solveAngles(g, base.R(t).transpose() * dir.at(t), prev).theta;
  };
  const double h = 1e-5;
  Vec2 prev = angles(0.0, Vec2::Zero());
  for (double t = 0.0; t < 8.0; t += 0.1) {
    const LosInBase l = losInBase(dir.at(t), dir.rate(t), base.R(t), base.omega(t));
    const Vec2 th = angles(t, prev);
    const Vec2 fd = (angles(t + h, th) - angles(t - h, th)) / (2.0 * h);
    EXPECT_LT((solveRates(g, th, l.d_B_dot) - fd).cwiseAbs().maxCoeff(), 1e-8) << "t = " << t;
    prev = th;
  }
}

TEST(GimbalIk, CurvatureMatchesASecondDifferenceOfTheBoresight) {
  // Joint angles moving at constant rates: b'' is the curvature term alone.
  const GimbalGeometry g = gimbalGeometry(test::model("paper_ideal"));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  const double h = 1e-4;
  for (int k = 0; k < 50; ++k) {
    const Vec2 th = randomAngles(rng), w{u(rng), u(rng)};
    const Vec3 fd = (boresightB(g, th + h * w) - 2.0 * boresightB(g, th) + boresightB(g, th - h * w)) / (h * h);
    EXPECT_LT((boresightCurvature(g, th, w) - fd).norm(), 1e-6 * (1.0 + w.squaredNorm())) << "k = " << k;
  }
}

TEST(GimbalIk, JointAccelerationsOfAnInertialTargetFromAnAcceleratingBase) {
  // The whole second-derivative feed-forward (target acceleration, base rate
  // and base angular acceleration, the IK's curvature) against the second
  // difference of the IK's angles; omega_B of RotatingBase turns in the base
  // frame, so its derivative alpha_B (a difference of the closed form here) is not zero.
  const GimbalGeometry g = gimbalGeometry(test::model("paper_ideal"));
  const RotatingBase base;
  const TurningDirection dir;
  auto angles = [&](double t, const Vec2& prev) {
    return solveAngles(g, base.R(t).transpose() * dir.at(t), prev).theta;
  };
  const double h = 1e-4, e = 1e-6;
  Vec2 prev = angles(0.0, Vec2::Zero());
  for (double t = 0.0; t < 8.0; t += 0.1) {
    const Vec3 alpha = (base.omega(t + e) - base.omega(t - e)) / (2.0 * e);
    ASSERT_GT(alpha.norm(), 1e-4);
    const Vec3 accel = dir.w * dir.a.cross(dir.rate(t));  // the target's inertial acceleration
    const LosInBase l = losInBase(dir.at(t), dir.rate(t), accel, base.R(t), base.omega(t), alpha);
    const auto dB = [&](double s) { return Vec3(base.R(s).transpose() * dir.at(s)); };
    EXPECT_LT((l.d_B_ddot - (dB(t + h) - 2.0 * dB(t) + dB(t - h)) / (h * h)).norm(), 1e-6) << "t = " << t;
    const Vec2 th = angles(t, prev);
    const Vec2 th_p = angles(t + h, th), th_m = angles(t - h, th);
    const Vec2 rate = (th_p - th_m) / (2.0 * h), acc = (th_p - 2.0 * th + th_m) / (h * h);
    EXPECT_LT((solveAccelerations(g, th, solveRates(g, th, l.d_B_dot), l.d_B_ddot) - acc).cwiseAbs().maxCoeff(),
              1e-5 * (1.0 + acc.cwiseAbs().maxCoeff()))
        << "t = " << t;
    EXPECT_LT((solveRates(g, th, l.d_B_dot) - rate).cwiseAbs().maxCoeff(), 1e-6) << "t = " << t;
    prev = th;
  }
}

TEST(GimbalIk, TiltedJointTwoConvergesByGaussNewton) {
  Model m = test::model("paper_ideal");
  m.k2_S1 = Vec3(0.08, 1.0, -0.05).normalized();
  m.boresight_S2 = Vec3(1.0, 0.1, 0.15).normalized();
  m.finalize();
  const GimbalGeometry g = gimbalGeometry(m);
  ASSERT_FALSE(g.closed_form);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.2, 1.2), jitter(-0.2, 0.2);
  int max_iterations = 0;
  for (int k = 0; k < 500; ++k) {
    const Vec2 truth{3.0 * u(rng), u(rng)};
    // The forward model agrees with the dynamics' kinematics for this geometry too.
    const Vec3 d_B = dynamicsBoresightB<FloatingIdeal>(m, truth, randomAttitude(rng));
    ASSERT_LT((d_B - boresightB(g, truth)).norm(), 1e-14);
    const IkSolution s = solveAngles(g, d_B, truth + Vec2(jitter(rng), jitter(rng)));
    EXPECT_TRUE(s.converged);
    EXPECT_NEAR((s.theta - truth).cwiseAbs().maxCoeff(), 0.0, kAngleTol) << "case " << k;
    EXPECT_LT(s.residual, 1e-14);
    max_iterations = std::max(max_iterations, s.iterations);
  }
  EXPECT_LE(max_iterations, 8);
  // The Jacobian is the derivative of the forward model.
  const Vec2 th{0.7, -0.4};
  const double h = 1e-6;
  const Mat32 J = boresightJacobian(g, th);
  for (int i = 0; i < 2; ++i) {
    const Vec2 e = h * Vec2::Unit(i);
    const Vec3 fd = (boresightB(g, th + e) - boresightB(g, th - e)) / (2.0 * h);
    EXPECT_LT((J.col(i) - fd).norm(), 1e-9);
  }
}

TEST(GimbalIk, KeyholeKeepsThePreviousAzimuth) {
  const GimbalGeometry g = gimbalGeometry(test::model("paper_ideal"));
  const Vec2 prev{0.7, -1.2};
  for (const Vec3& d : {Vec3(0.0, 0.0, 1.0), Vec3(0.0, 0.0, -1.0), Vec3(3e-8, -2e-8, 1.0)}) {
    const IkSolution s = solveAngles(g, d, prev);
    EXPECT_TRUE(s.singular);
    EXPECT_EQ(s.theta(0), prev(0));
    EXPECT_LT(s.residual, 1e-7);
    EXPECT_LT(std::abs(s.theta(1) - prev(1)), M_PI);
    EXPECT_EQ(solveRates(g, s.theta, Vec3(0.01, 0.02, 0.0))(0), 0.0);
  }
  // Just outside the tolerance: the azimuth is the direction's again.
  const IkSolution s = solveAngles(g, Vec3(1e-5 * std::cos(2.0), 1e-5 * std::sin(2.0), -1.0), prev);
  EXPECT_FALSE(s.singular);
  EXPECT_LT(s.residual, 1e-15);
}

using G = const GimbalGeometry&;
using V2 = const Vec2&;
using V3 = const Vec3&;
static_assert(noexcept(solveAngles(std::declval<G>(), std::declval<V3>(), std::declval<V2>())));
static_assert(noexcept(solveRates(std::declval<G>(), std::declval<V2>(), std::declval<V3>())));
static_assert(noexcept(losInBase(std::declval<V3>(), std::declval<V3>(), std::declval<const Mat3&>(),
                                 std::declval<V3>())));

}  // namespace
}  // namespace gimbalsim::controllers
