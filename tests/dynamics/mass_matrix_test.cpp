// The CRBA mass matrix and RNEA bias forces against an independent
// computation: world-frame Newton-Euler over body Jacobians that are obtained
// by finite differences of body poses (no spatial algebra shared with the
// library), plus the CRBA against columns of the RNEA.
#include <gtest/gtest.h>

#include <random>

#include "gimbalsim/dynamics/forward_dynamics.hpp"
#include "test_util.hpp"

namespace gimbalsim {
namespace {

struct Pose {
  Mat3 R;
  Vec3 c;  // centre of mass, inertial [m]
};

/// Joint j's relative motion at q, from the definition of its coordinates
/// (docs/MODEL.md): journal centre p_x u1 + p_y u2 and R = Rot(u1, alpha)
/// Rot(u2, beta) Rot(k, theta), in the parent's frame (ideal: p = 0, R = Rot(k, theta)).
template <class V, int j>
void jointMotion(const Vec3& k, const Vec3& u1, const Vec3& u2, const typename State<V>::VecQ& q, Mat3& R,
                 Vec3& p) {
  int i = State<V>::QJ + V::group(j);
  R.setIdentity();
  p.setZero();
  if constexpr (V::kind(j) != ClearanceKind::Ideal) {
    p = q(i) * u1 + q(i + 1) * u2;
    i += 2;
  }
  if constexpr (V::kind(j) == ClearanceKind::Spatial) {
    R = Eigen::AngleAxisd(q(i), u1).toRotationMatrix() * Eigen::AngleAxisd(q(i + 1), u2).toRotationMatrix();
    i += 2;
  }
  R = R * Eigen::AngleAxisd(q(i), k).toRotationMatrix();
}

/// Body poses (base, shaft 1, shaft 2) written directly from the geometry.
template <class V>
std::array<Pose, 3> poses(const Model& m, const typename State<V>::VecQ& q) {
  Mat3 R0 = Mat3::Identity();
  Vec3 p0 = Vec3::Zero();
  if constexpr (V::kFloating) {
    R0 = Eigen::Quaterniond(q(3), q(4), q(5), q(6)).normalized().toRotationMatrix();
    p0 = q.template head<3>();
  }
  Mat3 Rj1, Rj2;
  Vec3 pj1, pj2;
  jointMotion<V, 0>(m.k1_B, m.u1_B, m.u2_B, q, Rj1, pj1);
  jointMotion<V, 1>(m.k2_S1, m.u1_S1, m.u2_S1, q, Rj2, pj2);
  const Mat3 R1 = R0 * Rj1;
  const Vec3 j1 = p0 + R0 * (m.r_J1_B_B + pj1);
  const Mat3 R2 = R1 * Rj2;
  const Vec3 j2 = j1 + R1 * (m.r_J2_S1_S1 + pj2);
  return {Pose{R0, p0 + R0 * m.base.com}, Pose{R1, j1 + R1 * m.shaft1.com}, Pose{R2, j2 + R2 * m.shaft2.com}};
}

/// Configuration after moving with constant generalised velocity v for time
/// tau (fine RK4 of the kinematic equations, written independently).
template <class V>
typename State<V>::VecQ flow(const typename State<V>::VecQ& q0, const typename State<V>::VecV& v, double tau) {
  using VecQ = typename State<V>::VecQ;
  auto rate = [&](const VecQ& q) {
    VecQ qd = VecQ::Zero();
    constexpr int QJ = State<V>::QJ, NB = V::NB;
    if constexpr (V::kFloating) {
      const Eigen::Quaterniond quat(q(3), q(4), q(5), q(6));
      qd.template head<3>() = quat.normalized().toRotationMatrix() * v.template segment<3>(3);
      const Eigen::Quaterniond w(0.0, v(0), v(1), v(2));
      const Eigen::Quaterniond dq = quat * w;
      qd(3) = 0.5 * dq.w();
      qd(4) = 0.5 * dq.x();
      qd(5) = 0.5 * dq.y();
      qd(6) = 0.5 * dq.z();
    }
    for (int i = 0; i < V::NJ; ++i) qd(QJ + i) = v(NB + i);
    return qd;
  };
  const int n = 50;
  const double h = tau / n;
  VecQ q = q0;
  for (int i = 0; i < n; ++i) {
    const VecQ k1 = rate(q), k2 = rate(q + 0.5 * h * k1), k3 = rate(q + 0.5 * h * k2), k4 = rate(q + h * k3);
    q += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  return q;
}

/// World angular velocity and CoM velocity of each body for velocity v at q,
/// by central differences of the poses along the flow.
template <class V>
std::array<Vec6, 3> bodyVelocities(const Model& m, const typename State<V>::VecQ& q,
                                   const typename State<V>::VecV& v) {
  const double eps = 1e-5;
  const auto pp = poses<V>(m, flow<V>(q, v, eps));
  const auto pm = poses<V>(m, flow<V>(q, v, -eps));
  std::array<Vec6, 3> out;
  for (int b = 0; b < 3; ++b) {
    const Eigen::AngleAxisd aa(pp[b].R * pm[b].R.transpose());
    out[b] << aa.axis() * aa.angle() / (2 * eps), (pp[b].c - pm[b].c) / (2 * eps);
  }
  return out;
}

/// chainJointKind<V> and chainBodyMassless<V> at every chain index.
template <class V>
std::array<JointKind, V::NJ> kindsOf() {
  std::array<JointKind, V::NJ> k{};
  staticFor<V::NJ>([&](auto I) { k[I] = chainJointKind<V>(I); });
  return k;
}
template <class V>
std::array<bool, V::NJ> masslessOf() {
  std::array<bool, V::NJ> k{};
  staticFor<V::NJ>([&](auto I) { k[I] = chainBodyMassless<V>(I); });
  return k;
}

template <class V>
void checkAgainstNewtonEuler(const std::string& scene_name, const std::vector<std::string>& sets) {
  const Scene sc = test::scene(scene_name, sets);
  // The joint kinds of V, whichever the scene file names (the scene keys
  // reach only some of them).
  Model m = sc.model;
  m.joint1_kind = V::kKind1;
  m.joint2_kind = V::kKind2;
  m.finalize();
  for (int i = 0; i < V::NJ; ++i) {
    ASSERT_EQ(m.chain[i].kind, (kindsOf<V>()[i])) << "chain joint " << i;
    ASSERT_EQ(m.I_chain[i].m == 0.0, (masslessOf<V>()[i])) << "chain body " << i;
  }
  using VecV = typename State<V>::VecV;
  using MatV = typename Data<V>::MatV;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const std::array<const BodyParams*, 3> body = {&m.base, &m.shaft1, &m.shaft2};
  for (int trial = 0; trial < 3; ++trial) {
    State<V> s = initialState<V>(sc.run.initial);
    for (int i = 0; i < V::NQ; ++i) s.q(i) = U(rng);
    for (int i = 0; i < V::NV; ++i) s.v(i) = U(rng);
    if constexpr (V::kFloating) s.q.template segment<4>(3).normalize();
    for (int i = 0; i < V::NJ; ++i) {  // journal centres within a clearance's size
      if (m.chain[i].kind == JointKind::Prismatic) s.q(State<V>::QJ + i) *= 4e-4;
    }
    Data<V> d(m);
    kinematics(m, d, s.q, s.v);
    crba(m, d);
    VecV C;
    rnea(m, d, s.v, VecV::Zero().eval(), C);

    // Jacobians J_b (6 x NV) of [omega; v_com] (world) by columns.
    std::array<Eigen::Matrix<double, 6, V::NV>, 3> J;
    for (int j = 0; j < V::NV; ++j) {
      const auto bv = bodyVelocities<V>(m, s.q, VecV::Unit(j));
      for (int b = 0; b < 3; ++b) J[b].col(j) = bv[b];
    }
    const auto P = poses<V>(m, s.q);
    MatV M_ne = MatV::Zero();
    VecV C_ne = VecV::Zero();
    // d/dt (J v) along the motion: second-order central difference.
    const double eps = 1e-4;
    const auto vp = bodyVelocities<V>(m, flow<V>(s.q, s.v, eps), s.v);
    const auto vm = bodyVelocities<V>(m, flow<V>(s.q, s.v, -eps), s.v);
    const auto v0 = bodyVelocities<V>(m, s.q, s.v);
    for (int b = 0; b < 3; ++b) {
      if (!V::kFloating && b == 0) continue;
      const Mat3 Iw = P[b].R * body[b]->inertia * P[b].R.transpose();
      Eigen::Matrix<double, 6, 6> Mb = Eigen::Matrix<double, 6, 6>::Zero();
      Mb.topLeftCorner<3, 3>() = Iw;
      Mb.bottomRightCorner<3, 3>() = body[b]->mass * Mat3::Identity();
      M_ne += J[b].transpose() * Mb * J[b];
      const Vec6 Jdv = (vp[b] - vm[b]) / (2 * eps);
      const Vec3 w = v0[b].template head<3>();
      Vec6 wrench;
      wrench << Iw * Jdv.template head<3>() + w.cross(Iw * w), body[b]->mass * Jdv.template tail<3>();
      C_ne += J[b].transpose() * wrench;
    }
    const MatV M_sym = 0.5 * (d.M + d.M.transpose());
    EXPECT_LT((d.M - M_sym).norm(), 1e-12 * d.M.norm()) << "M not symmetric";
    EXPECT_LT((d.M - M_ne).norm(), 1e-7 * d.M.norm()) << "CRBA:\n" << d.M << "\nNewton-Euler:\n" << M_ne;
    EXPECT_LT((C - C_ne).norm(), 1e-5 * (C.norm() + 1e-3)) << "RNEA: " << C.transpose()
                                                            << "\nNewton-Euler: " << C_ne.transpose();

    // CRBA against columns of the RNEA at zero velocity: M e_j = RNEA(q, 0, e_j).
    Data<V> d0(m);
    const VecV zero = VecV::Zero();
    kinematics(m, d0, s.q, zero);
    MatV M_rnea;
    for (int j = 0; j < V::NV; ++j) {
      VecV col;
      rnea(m, d0, zero, VecV::Unit(j).eval(), col);
      M_rnea.col(j) = col;
    }
    EXPECT_LT((d.M - M_rnea).norm(), 1e-12 * d.M.norm());
  }
}

TEST(MassMatrix, FloatingIdealAgreesWithNewtonEuler) {
  checkAgainstNewtonEuler<FloatingIdeal>("paper_ideal", {});
}
TEST(MassMatrix, FloatingClearanceAgreesWithNewtonEuler) {
  checkAgainstNewtonEuler<FloatingClearance>("paper_clearance", {"friction.law=none"});
}
TEST(MassMatrix, FixedIdealAgreesWithNewtonEuler) {
  checkAgainstNewtonEuler<FixedIdeal>("paper_ideal", {"structure.base=fixed"});
}
TEST(MassMatrix, FixedClearanceAgreesWithNewtonEuler) {
  checkAgainstNewtonEuler<FixedClearance>("paper_clearance", {"structure.base=fixed", "friction.law=none"});
}
TEST(MassMatrix, PlanarClearanceAgreesWithNewtonEuler) {
  checkAgainstNewtonEuler<FloatingClearance>("planar_clearance", {"friction.law=none"});
}

// Every joint kind in either joint (planar: [p_x, p_y, theta]; spatial:
// [p_x, p_y, alpha, beta, theta]), including a prismatic first chain joint.
using CK = ClearanceKind;
TEST(MassMatrix, ClearanceJoint1AgreesWithNewtonEuler) {
  checkAgainstNewtonEuler<Variant<true, CK::Planar, CK::Ideal, false>>("paper_ideal", {});
  checkAgainstNewtonEuler<Variant<false, CK::Planar, CK::Planar, false>>("paper_ideal", {"structure.base=fixed"});
}
TEST(MassMatrix, SpatialJointsAgreeWithNewtonEuler) {
  checkAgainstNewtonEuler<Variant<true, CK::Ideal, CK::Spatial, false>>("paper_ideal", {});
  checkAgainstNewtonEuler<Variant<true, CK::Spatial, CK::Planar, false>>("paper_ideal", {});
  checkAgainstNewtonEuler<Variant<true, CK::Spatial, CK::Spatial, false>>("paper_ideal", {});
  checkAgainstNewtonEuler<Variant<false, CK::Spatial, CK::Spatial, false>>("paper_ideal", {"structure.base=fixed"});
}

}  // namespace
}  // namespace gimbalsim
