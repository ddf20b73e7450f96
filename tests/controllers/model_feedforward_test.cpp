// The computed-torque feed-forward's model (model_feedforward.hpp) against the
// plant: the default configuration's plant.* keys describe the paper scene, and
// the torque tau = H* ddq + c* fed to the PLANT's forward dynamics (the scene
// file's Model, Cholesky of the full 8x8 M) gives back the wanted joint
// accelerations and the predicted base angular acceleration.
#include <gtest/gtest.h>

#include "gimbalsim/controllers/config.hpp"
#include "gimbalsim/controllers/model_feedforward.hpp"
#include "gimbalsim/dynamics/forward_dynamics.hpp"
#include "test_util.hpp"

namespace gimbalsim::controllers {
namespace {

struct Case {
  Vec2 q, dq, ddq;
  Vec3 omega_B;
};

/// The plant's response to tau at (q, dq, omega_B) with zero linear momentum (v_B solved here from M's base rows).
Data<FloatingIdeal>::VecV plantAccelerations(const Model& m, const Case& k, const Vec2& tau) {
  using V = FloatingIdeal;
  Data<V> d(m);
  State<V> s;
  s.q(3) = 1.0;
  s.q.tail<2>() = k.q;
  s.v.head<3>() = k.omega_B;
  s.v.tail<2>() = k.dq;
  kinematics(m, d, s.q, s.v);
  crba(m, d);
  s.v.segment<3>(3) = -(d.M.block<3, 3>(3, 0) * k.omega_B + d.M.block<3, 2>(3, 6) * k.dq) / d.M(3, 3);
  Input u;
  u.tau = tau;
  forwardDynamics(m, d, s, u);
  return d.vdot;
}

TEST(ModelFeedForward, TheDefaultPlantModelsTorqueGivesThePaperScenesPlantTheWantedAccelerations) {
  const ControllerConfig c = loadControllerConfig(test::defaultControllerConfig());
  const Model plant = test::scene("paper_ideal").model;
  const Case cases[] = {
      {{0.0, 0.0}, {0.0, 0.0}, {1.0, -2.0}, {0.0, 0.0, 0.0}},            // from rest: H* alone
      {{0.5, 0.3}, {0.2, -0.15}, {0.3, 0.7}, {0.01, -0.02, -0.03}},      // with the velocity terms
      {{-1.2, -0.8}, {-0.4, 0.5}, {-0.6, 0.1}, {-0.002, 0.004, 0.05}},
  };
  for (const Case& k : cases) {
    const ReducedDynamics r = reducedDynamics(c.plant_model, k.q, k.dq, k.omega_B);
    const auto vdot = plantAccelerations(plant, k, r.H * k.ddq + r.c);
    EXPECT_NEAR(vdot(6), k.ddq(0), 1e-12 * (1.0 + std::abs(k.ddq(0))));
    EXPECT_NEAR(vdot(7), k.ddq(1), 1e-12 * (1.0 + std::abs(k.ddq(1))));
    const Vec3 alpha_B = -(r.A * k.ddq + r.a0);
    EXPECT_LT((vdot.head<3>() - alpha_B).norm(), 1e-12 * (1.0 + alpha_B.norm()));
  }
  // H* is the free base's: less than the fixed base's joint-1 inertia 17.6 kg m^2 (shaft 2 horizontal).
  const ReducedDynamics r0 = reducedDynamics(c.plant_model, Vec2::Zero(), Vec2::Zero(), Vec3::Zero());
  EXPECT_LT(r0.H(0, 0), 17.6);
  EXPECT_GT(r0.H(0, 0), 0.0);
}

TEST(ModelFeedForward, PointingAccelerationsTurnTheBoresightAsWantedWithTheBasesReaction) {
  const ControllerConfig c = loadControllerConfigText("", "defaults");
  const GimbalGeometry g = gimbalGeometry(c.gimbal.joint1_axis, c.gimbal.joint2_axis, c.gimbal.boresight);
  const Vec2 q{0.4, 0.25}, dq{0.05, -0.03}, ddq_wanted{0.8, -1.1};
  const ReducedDynamics r = reducedDynamics(c.plant_model, q, dq, Vec3(0.001, -0.002, -0.01));
  const Vec3 d_B = boresightB(g, q);
  // The boresight's second derivative in the base frame these accelerations give, base reaction included,
  // written as what losInBase reports with alpha_B = 0: d_B_ddot = d_B_ddot0 - alpha_B x d_B.
  const Vec3 alpha_B = -(r.A * ddq_wanted + r.a0);
  const Vec3 d_B_ddot0 = boresightJacobian(g, q) * ddq_wanted + boresightCurvature(g, q, dq) + alpha_B.cross(d_B);
  const Vec2 ddq = pointingAccelerations(g, r, q, dq, d_B, d_B_ddot0);
  EXPECT_NEAR(ddq(0), ddq_wanted(0), 1e-12);
  EXPECT_NEAR(ddq(1), ddq_wanted(1), 1e-12);
}

}  // namespace
}  // namespace gimbalsim::controllers
