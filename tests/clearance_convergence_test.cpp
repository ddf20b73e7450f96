// As the clearance shrinks with stiff contact, the clearance run approaches
// the ideal run (docs/MODEL.md section 8.7).
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace gimbalsim
