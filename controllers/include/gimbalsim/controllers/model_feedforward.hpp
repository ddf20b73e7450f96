// Computed-torque feed-forward from the free-floating plant's exact rigid-body
// model (pointing.accel_feedforward = model). The controller holds a Model
// built from its plant.* mass-property keys (plantModel(), at load) and, each
// period, runs the dynamics library's CRBA and RNEA on it at the reference.
//
// Free-floating base, no external force, zero total momentum (the plant starts
// at rest): with M = [Mbb Mbq; Mqb Mqq] and bias C = [Cb; Cq] at
// (q_ref, omega_B, v_B, dq_ref), v_B from zero linear momentum,
//   base:   Mbb vb_dot + Mbq ddq + Cb = 0  ->  vb_dot = -(X ddq + y),
//           X = Mbb^-1 Mbq, y = Mbb^-1 Cb
//   joints: tau = H* ddq + c*,  H* = Mqq - Mqb X,  c* = Cq - Mqb y
// and the base's angular acceleration alpha_B = -(X ddq + y)(0:3) enters the
// boresight's second derivative, so ddq solves the inertial pointing
// directly (no measured, filtered alpha_B):
//   J ddq + curvature - alpha_B x d_B = d_B_ddot(alpha_B = 0)
//   (J + [d_B]x X_w) ddq = d_B_ddot(0) - curvature - [d_B]x y_w   (least squares).
// Allocation-free and noexcept (fixed-size Eigen, Data on the stack).
#pragma once

#include "gimbalsim/controllers/gimbal_ik.hpp"
#include "gimbalsim/dynamics/model.hpp"

namespace gimbalsim::controllers {

using Mat2 = Eigen::Matrix<double, 2, 2>;

/// Mass properties of the plant the feed-forward assumes (keys plant.*), frames as the scene's (docs/MODEL.md).
struct PlantMass {
  BodyParams base;            ///< mass [kg], inertia about the base CoM, base frame [kg m^2] (com unused: 0)
  BodyParams shaft1;          ///< com from joint 1, shaft 1 frame [m]; inertia about its CoM, shaft 1 frame
  BodyParams shaft2;          ///< com from joint 2, shaft 2 frame [m]; inertia about its CoM, shaft 2 frame
  Vec3 joint1_position_B = Vec3(0.0, 0.0, 0.5);   ///< joint 1 from the base CoM, base frame [m]
  Vec3 joint2_position_S1 = Vec3(0.0, 0.0, 1.0);  ///< joint 2 from joint 1, shaft 1 frame [m]
};

/// The paper scene's values (tools/scenes/paper_ideal.yaml).
PlantMass paperPlantMass();

/// The floating-base, ideal-joint Model of these mass properties and axes (finalized).
Model plantModel(const PlantMass& p, const Vec3& joint1_axis_B, const Vec3& joint2_axis_S1,
                 const Vec3& boresight_S2);

/// The reduced joint-space dynamics at one instant: tau = H ddq + c, alpha_B = -(A ddq + a0).
struct ReducedDynamics {
  Mat2 H = Mat2::Zero();                         ///< H* [kg m^2]
  Vec2 c = Vec2::Zero();                         ///< c* [N m]
  Eigen::Matrix<double, 3, 2> A = Eigen::Matrix<double, 3, 2>::Zero();  ///< X's angular rows [-]
  Vec3 a0 = Vec3::Zero();                        ///< y's angular rows [rad/s^2]
  double joint_scale = 0.0;  ///< [kg m^2] the largest entry of Mqq, which H* is the base's reaction short of
};

/// H*, c* and the base's angular response at joint angles q [rad], joint rates
/// dq [rad/s] and base rate omega_B [rad/s, base frame]. m: a plantModel().
ReducedDynamics reducedDynamics(const Model& m, const Vec2& q, const Vec2& dq, const Vec3& omega_B) noexcept;

/// The joint accelerations [rad/s^2] that give the boresight the second
/// derivative d_B_ddot0 - alpha_B x d_B in the base frame, alpha_B the base's
/// reaction to them (r: at q, dq; d_B_ddot0: losInBase's d_B_ddot with alpha_B = 0).
Vec2 pointingAccelerations(const GimbalGeometry& g, const ReducedDynamics& r, const Vec2& q, const Vec2& dq,
                           const Vec3& d_B, const Vec3& d_B_ddot0) noexcept;

}  // namespace gimbalsim::controllers
