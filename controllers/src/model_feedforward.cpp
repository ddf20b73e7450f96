#include "gimbalsim/controllers/model_feedforward.hpp"

#include <Eigen/LU>
#include <cmath>

#include "gimbalsim/dynamics/crba.hpp"
#include "gimbalsim/dynamics/data.hpp"
#include "gimbalsim/dynamics/mass_factor.hpp"
#include "gimbalsim/dynamics/rnea.hpp"

namespace gimbalsim::controllers {

PlantMass paperPlantMass() {
  PlantMass p;
  p.base.mass = 1000.0;
  p.base.inertia = Vec3(1000.0, 100.0, 100.0).asDiagonal();
  p.shaft1.mass = 10.0;
  p.shaft1.com = Vec3(0.0, 0.0, 0.5);
  p.shaft1.inertia = Vec3(1.0, 1.0, 0.1).asDiagonal();
  p.shaft2.mass = 50.0;
  p.shaft2.com = Vec3(0.5, 0.0, 0.0);
  p.shaft2.inertia = Vec3(0.5, 5.0, 5.0).asDiagonal();
  return p;
}

Model plantModel(const PlantMass& p, const Vec3& joint1_axis_B, const Vec3& joint2_axis_S1,
                 const Vec3& boresight_S2) {
  Model m;
  m.name = "controller plant model";
  m.floating_base = true;
  m.joint1_kind = ClearanceKind::Ideal;  // the controller models ideal joints
  m.joint2_kind = ClearanceKind::Ideal;
  m.base = p.base;
  m.base.com.setZero();  // the base frame's origin is its CoM
  m.shaft1 = p.shaft1;
  m.shaft2 = p.shaft2;
  m.r_J1_B_B = p.joint1_position_B;
  m.r_J2_S1_S1 = p.joint2_position_S1;
  m.k1_B = joint1_axis_B;
  m.k2_S1 = joint2_axis_S1;
  m.boresight_S2 = boresight_S2;
  m.finalize();
  return m;
}

ReducedDynamics reducedDynamics(const Model& m, const Vec2& q, const Vec2& dq, const Vec3& omega_B) noexcept {
  using V = FloatingIdeal;
  Data<V> d(m);
  // The body-frame dynamics do not depend on the base's pose: identity at the origin.
  Eigen::Matrix<double, V::NQ, 1> qv = Eigen::Matrix<double, V::NQ, 1>::Zero();
  qv(3) = 1.0;
  qv.tail<2>() = q;
  Eigen::Matrix<double, V::NV, 1> v = Eigen::Matrix<double, V::NV, 1>::Zero();
  v.head<3>() = omega_B;
  v.tail<2>() = dq;
  kinematics(m, d, qv, v);
  crba(m, d);
  // Zero linear momentum (base rows 3..5 of M v; M(3:6, 3:6) = total mass 1): the base CoM's velocity.
  v.segment<3>(3) = -(d.M.block<3, 3>(3, 0) * omega_B + d.M.block<3, 2>(3, 6) * dq) / d.M(3, 3);
  kinematics(m, d, qv, v);
  const Eigen::Matrix<double, V::NV, 1> zero = Eigen::Matrix<double, V::NV, 1>::Zero();
  Eigen::Matrix<double, V::NV, 1> C;
  rnea(m, d, v, zero, C);
  // The plant's own factorisation: the base block inverted in closed form about the CoM (mass_factor.hpp).
  MassFactor<V> F;
  factorMass<V>(d.M, F);
  const Eigen::Matrix<double, 6, 2> Mbq = d.M.topRightCorner<6, 2>();
  Vec6 y;
  detail::baseBlockSolve(F, C.data(), y.data());
  ReducedDynamics r;
  r.H = d.M.bottomRightCorner<2, 2>() - Mbq.transpose() * F.Y;
  r.c = C.tail<2>() - Mbq.transpose() * y;
  r.A = F.Y.topRows<3>();
  r.a0 = y.head<3>();
  r.joint_scale = d.M.bottomRightCorner<2, 2>().cwiseAbs().maxCoeff();
  return r;
}

Vec2 pointingAccelerations(const GimbalGeometry& g, const ReducedDynamics& r, const Vec2& q, const Vec2& dq,
                           const Vec3& d_B, const Vec3& d_B_ddot0) noexcept {
  // alpha_B = -(A ddq + a0): -alpha_B x d_B = (A ddq + a0) x d_B = -[d_B]x (A ddq + a0).
  Mat3 dx;
  dx << 0.0, -d_B.z(), d_B.y(), d_B.z(), 0.0, -d_B.x(), -d_B.y(), d_B.x(), 0.0;
  const Mat32 K = boresightJacobian(g, q) + dx * r.A;
  const Vec3 rhs = d_B_ddot0 - boresightCurvature(g, q, dq) - dx * r.a0;
  // Normal equations of the 3x2 least-squares problem (K has full rank off the keyhole).
  const Mat2 KtK = K.transpose() * K;
  const double det = KtK.determinant();
  if (!(std::abs(det) > 1e-12 * KtK(0, 0) * KtK(1, 1))) {
    return {0.0, KtK(1, 1) > 0.0 ? K.col(1).dot(rhs) / KtK(1, 1) : 0.0};
  }
  return KtK.inverse() * (K.transpose() * rhs);
}

}  // namespace gimbalsim::controllers
