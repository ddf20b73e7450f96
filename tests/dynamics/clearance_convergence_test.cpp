// As the clearance shrinks with stiff contact, the clearance run approaches
// the ideal run (docs/MODEL.md section 8.7).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "test_util.hpp"

namespace gimbalsim {
namespace {

TEST(ClearanceConvergence, ShrinkingClearanceApproachesTheIdealJoint) {
  const double T = 0.5;
  const Scene sci = test::scene("paper_ideal");
  const auto ideal = test::runTo<FloatingIdeal>(sci, T);
  const Vec3 b_ideal = test::boresightOf(sci.model, ideal);
  std::vector<double> err, err_theta;
  for (const char* c : {"5.0e-4", "5.0e-5", "5.0e-6"}) {
    const Scene sc = test::scene("paper_clearance", {std::string("contact.clearance=") + c,
                                                     "contact.radius_mode=conformal", "contact.stiffness_scale=10",
                                                     "friction.law=none", "sim.substep=5e-6"});
    const auto s = test::runTo<FloatingClearance>(sc, T);
    err.push_back(test::angleBetween(test::boresightOf(sc.model, s), b_ideal));
    err_theta.push_back(std::fabs(s.theta(1) - ideal.theta(1)) + std::fabs(s.theta(0) - ideal.theta(0)));
  }
  for (size_t i = 0; i + 1 < err.size(); ++i) {
    EXPECT_LT(err[i + 1], 0.5 * err[i]) << "boresight error must shrink with the clearance";
    EXPECT_LT(err_theta[i + 1], 0.5 * err_theta[i]);
  }
  EXPECT_LT(err.back(), 1e-4) << "5 um clearance: boresight within 0.1 mrad of the ideal joint";
}

/// The same for clearance in either joint, planar or spatial (the page's
/// check 4): every clearance joint's bearing shrinks together. The largest
/// boresight error over the run (a journal rattling between its bearing's
/// ends makes the error at one instant erratic; its bound shrinks with c).
template <class V>
void expectApproachesIdeal(const std::vector<std::string>& kinds, double final_tol) {
  const int steps = 500;  // 0.5 s
  const Scene sci = test::scene("paper_ideal");
  std::vector<Vec3> b_ideal;
  {
    Data<FloatingIdeal> d(sci.model);
    auto s = initialState<FloatingIdeal>(sci.run.initial);
    for (int k = 0; k < steps; ++k) {
      test::advance(sci.model, d, s, 1, Input{sci.run.torque});
      b_ideal.push_back(test::boresightOf(sci.model, s));
    }
  }
  std::vector<double> err;
  std::string name;
  for (const char* c : {"5.0e-4", "5.0e-5", "5.0e-6"}) {
    // The journals rattle: up to 22 located switches in one 1 ms step (two
    // spatial joints, 4 ends), beyond the automatic cap's room for 4, so the cap is set.
    std::vector<std::string> sets = {std::string("contact.clearance=") + c, "contact.radius_mode=conformal",
                                     "contact.stiffness_scale=10", "friction.law=none", "sim.substep=5e-6",
                                     "sim.max_substeps=1000"};
    sets.insert(sets.end(), kinds.begin(), kinds.end());
    const Scene sc = test::scene("paper_clearance", sets);
    name = variantName(sc.model);
    ASSERT_EQ(name, shapeName(V::kFloating, V::kKind1, V::kKind2, V::kFriction));
    Data<V> d(sc.model);
    auto s = initialState<V>(sc.run.initial);
    double worst = 0.0;
    for (int k = 0; k < steps; ++k) {
      test::advance(sc.model, d, s, 1, Input{sc.run.torque});
      worst = std::max(worst, test::angleBetween(test::boresightOf(sc.model, s), b_ideal[k]));
    }
    err.push_back(worst);
  }
  std::printf("%s: largest boresight error against the ideal joint over 0.5 s: %.3g, %.3g, %.3g rad\n",
              name.c_str(), err[0], err[1], err[2]);
  for (size_t i = 0; i + 1 < err.size(); ++i) {
    EXPECT_LT(err[i + 1], 0.5 * err[i]) << "boresight error must shrink with the clearance";
  }
  EXPECT_LT(err.back(), final_tol);
}

TEST(ClearanceConvergence, ClearanceInEitherJointApproachesTheIdealJoint) {
  using CK = ClearanceKind;
  expectApproachesIdeal<Variant<true, CK::Ideal, CK::Spatial, false>>({"structure.joint2=spatial"}, 1e-4);
  expectApproachesIdeal<Variant<true, CK::Planar, CK::Planar, false>>({"structure.joint1=planar"}, 1e-4);
  // Two tilting journals: each may tilt by up to 2 c / L = 2e-4 rad at c = 5 um
  // (L = 0.05 m), so the boresight may stray by their sum.
  expectApproachesIdeal<Variant<true, CK::Spatial, CK::Spatial, false>>(
      {"structure.joint1=spatial", "structure.joint2=spatial"}, 2.0 * 2.0 * 5e-6 / 0.05);
}

}  // namespace
}  // namespace gimbalsim
