// The specialised solve of M vdot = b (mass_factor.hpp: closed-form base
// block, Schur complement over the chain) against the independent dense
// Cholesky of the CRBA's M, on random states of every compiled shape.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "gimbalsim/dynamics/forward_dynamics.hpp"
#include "test_util.hpp"

namespace gimbalsim {
namespace {

/// Largest |x_a - x_b| / |x_b| allowed between two backward-stable solves of
/// M x = b: a few units of kappa(M) times the machine epsilon.
template <int N>
double roundOffBound(const Eigen::Matrix<double, N, N>& M) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> es(M, Eigen::EigenvaluesOnly);
  const double kappa = es.eigenvalues().maxCoeff() / es.eigenvalues().minCoeff();
  return 16.0 * N * kappa * std::numeric_limits<double>::epsilon();
}

template <class V>
void checkShape(std::mt19937& rng, double* worst) {
  Model m = test::model("paper_ideal", {V::kFloating ? "structure.base=floating" : "structure.base=fixed"});
  m.joint1_kind = V::kKind1;
  m.joint2_kind = V::kKind2;
  m.finalize();
  using VecV = typename State<V>::VecV;
  using MatV = typename Data<V>::MatV;
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const std::string name = shapeName(V::kFloating, V::kKind1, V::kKind2, V::kFriction);
  for (int trial = 0; trial < 4; ++trial) {
    State<V> s = initialState<V>(InitialParams{});
    for (int i = 0; i < V::NQ; ++i) s.q(i) = U(rng);
    for (int i = 0; i < V::NV; ++i) s.v(i) = U(rng);
    if constexpr (V::kFloating) s.q.template segment<4>(3).normalize();
    for (int i = 0; i < V::NJ; ++i) {  // journal centres near the clearance (about 1 mm)
      if (m.chain[i].kind == JointKind::Prismatic) s.q(State<V>::QJ + i) *= 1e-3;
    }
    Data<V> d(m);
    kinematics(m, d, s.q, s.v);
    crba(m, d);
    VecV b;
    for (int i = 0; i < V::NV; ++i) b(i) = 100.0 * U(rng);

    MassFactor<V> F;
    ASSERT_TRUE(factorMass(d.M, F)) << name;
    EXPECT_TRUE(F.ok);
    VecV x_schur, x_dense;
    solveMass(F, b, x_schur);
    MatV L;
    ASSERT_TRUE(choleskySolve(d.M, L, [&](int j) { return b(j); }, x_dense)) << name;
    const double rel = (x_schur - x_dense).norm() / x_dense.norm();
    EXPECT_LE(rel, roundOffBound<V::NV>(d.M)) << name << " trial " << trial << "\nschur " << x_schur.transpose()
                                              << "\ndense " << x_dense.transpose();
    *worst = std::fmax(*worst, rel);

    // forwardDynamics itself: vdot solves M vdot = tau - C with the tau it applied.
    const Input u{Vec2(U(rng), U(rng))};
    forwardDynamics(m, d, s, u);
    VecV vdot_dense;
    ASSERT_TRUE(choleskySolve(d.M, L, [&](int j) { return d.tau(j) - d.bias(j); }, vdot_dense)) << name;
    EXPECT_LE((d.vdot - vdot_dense).norm(), roundOffBound<V::NV>(d.M) * vdot_dense.norm()) << name;
  }
}

TEST(ForwardDynamics, SchurSolveAgreesWithDenseCholeskyOnEveryShape) {
  std::mt19937 rng(11);
  double worst = 0.0;
#define GIMBALSIM_CHECK_SHAPE(FL, K1, K2, FR) checkShape<GIMBALSIM_SHAPE(FL, K1, K2, FR)>(rng, &worst);
  GIMBALSIM_FOR_EACH_SHAPE(GIMBALSIM_CHECK_SHAPE)
#undef GIMBALSIM_CHECK_SHAPE
  // Round-off in absolute terms too: no shape loses more than 6 digits.
  EXPECT_LT(worst, 1e-10);
  RecordProperty("worst_relative_difference", std::to_string(worst));
}

/// A matrix that is not positive definite is refused, in the base block or
/// in the chain's Schur complement, and forwardDynamics then returns NaN.
TEST(ForwardDynamics, IndefiniteMassMatrixIsRefused) {
  using V = FloatingClearance;
  const Model m = test::model("paper_clearance");
  Data<V> d(m);
  const State<V> s = initialState<V>(InitialParams{});
  kinematics(m, d, s.q, s.v);
  crba(m, d);
  MassFactor<V> F;
  ASSERT_TRUE(factorMass(d.M, F));
  typename Data<V>::MatV M = d.M;
  M(3, 3) = M(4, 4) = M(5, 5) = -1.0;  // negative total mass: the base block
  EXPECT_FALSE(factorMass(M, F));
  EXPECT_FALSE(F.ok);
  M = d.M;
  M(V::NV - 1, V::NV - 1) = 0.0;  // elevation angle with no inertia: the Schur complement
  EXPECT_FALSE(factorMass(M, F));
  MassFactor<FixedIdeal> Ff;
  Eigen::Matrix2d Mf;
  Mf << 1.0, 2.0, 2.0, 1.0;  // eigenvalues 3 and -1
  EXPECT_FALSE(factorMass(Mf, Ff));
}

}  // namespace
}  // namespace gimbalsim
