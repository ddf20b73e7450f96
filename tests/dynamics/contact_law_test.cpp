// Contact law of the clearance joint (docs/MODEL.md section 4).
#include <gtest/gtest.h>

#include "gimbalsim/dynamics/contact_law.hpp"
#include "test_util.hpp"

namespace gimbalsim {
namespace {

TEST(ContactLaw, HertzStiffnessOfBothRadiusModes) {
  // Paper's materials: K = 8.676e9 (paper, convex-convex R) and 5.418e10
  // N/m^1.5 (conformal R) as computed independently in docs/MODEL.md section 4.6.
  ContactParams c;
  EXPECT_NEAR(Model::hertzStiffness(c, RadiusMode::Paper), 8.676e9, 0.0005 * 8.676e9);
  EXPECT_NEAR(Model::hertzStiffness(c, RadiusMode::Conformal), 5.418e10, 0.0005 * 5.418e10);
  // The scene loader derives the same K and the clearance.
  const Model m = test::model("paper_clearance");
  EXPECT_NEAR(m.bearing[1].K, 8.676e9, 0.0005 * 8.676e9);
  EXPECT_NEAR(m.bearing[1].clearance, 0.5e-3, 1e-15);
  const Model mc = test::model("paper_clearance", {"contact.radius_mode=conformal"});
  EXPECT_NEAR(mc.bearing[1].K, 5.418e10, 0.0005 * 5.418e10);
}

/// Effective restitution of one normal impact of a point mass against the
/// contact law: integrated finely from first touch until it leaves.
double effectiveRestitution(DampingLaw law, double ce) {
  ContactParams c;
  c.damping = law;
  c.restitution = ce;
  c.K = Model::hertzStiffness(c, RadiusMode::Paper);
  c.chi = dampingFactor(law, ce);
  const double mass = 10.0, vin = 0.1, h = 2e-8;
  double x = 0.0, v = vin;  // x = penetration [m], v = d(delta)/dt
  auto acc = [&](double xx, double vv) { return -normalForce(c, xx, vv, vin) / mass; };
  for (int i = 0; i < 10'000'000; ++i) {
    const double k1x = v, k1v = acc(x, v);
    const double k2x = v + 0.5 * h * k1v, k2v = acc(x + 0.5 * h * k1x, v + 0.5 * h * k1v);
    const double k3x = v + 0.5 * h * k2v, k3v = acc(x + 0.5 * h * k2x, v + 0.5 * h * k2v);
    const double k4x = v + h * k3v, k4v = acc(x + h * k3x, v + h * k3v);
    x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    if (x < 0.0 && v < 0.0) return -v / vin;
  }
  return -1.0;
}

TEST(ContactLaw, PureHertzIsElastic) {
  EXPECT_NEAR(effectiveRestitution(DampingLaw::None, 0.5), 1.0, 1e-6);
  EXPECT_NEAR(effectiveRestitution(DampingLaw::LankaraniNikravesh, 1.0), 1.0, 1e-6);
}

TEST(ContactLaw, EveryDampingLawMatchesHighRestitution) {
  // All three laws are derived for (or valid at) restitution close to 1.
  for (DampingLaw law : {DampingLaw::HuntCrossley, DampingLaw::LankaraniNikravesh, DampingLaw::Flores}) {
    EXPECT_NEAR(effectiveRestitution(law, 0.95), 0.95, 0.01) << static_cast<int>(law);
    EXPECT_NEAR(effectiveRestitution(law, 0.9), 0.9, 0.015) << static_cast<int>(law);
  }
}

TEST(ContactLaw, FloresHoldsAtLowRestitutionWhereLankaraniNikraveshDoesNot) {
  for (double ce : {0.3, 0.5, 0.7}) {
    const double fl = effectiveRestitution(DampingLaw::Flores, ce);
    const double ln = effectiveRestitution(DampingLaw::LankaraniNikravesh, ce);
    EXPECT_NEAR(fl, ce, 0.05) << "Flores at c_e = " << ce;
    EXPECT_GT(ln - ce, 0.09) << "Lankarani-Nikravesh is known to overshoot at c_e = " << ce;
    EXPECT_LT(std::fabs(fl - ce), std::fabs(ln - ce));
  }
}

TEST(ContactLaw, NormalForceNeverPullsAndVanishesWhenSeparated) {
  ContactParams c;
  c.K = 1e10;
  c.chi = dampingFactor(DampingLaw::LankaraniNikravesh, 0.5);
  EXPECT_EQ(normalForce(c, -1e-6, 1.0, 0.1), 0.0);
  EXPECT_EQ(normalForce(c, 0.0, 1.0, 0.1), 0.0);
  EXPECT_EQ(normalForce(c, 1e-6, -100.0, 0.1), 0.0);  // fast rebound: clamped, no adhesion
  EXPECT_GT(normalForce(c, 1e-6, 0.0, 0.1), 0.0);
  EXPECT_NEAR(normalForce(c, 1e-6, 0.0, 0.1), 1e10 * 1e-9, 1e-6);
}

TEST(ContactLaw, FrictionIsSymmetricInTheSignOfTangentialVelocity) {
  for (FrictionLaw law : {FrictionLaw::Coulomb, FrictionLaw::Ambrosio}) {
    ContactParams c;
    c.friction = law;
    c.mu = 0.25;
    for (double vt : {5e-5, 2e-4, 5e-4, 1e-3, 0.3}) {
      const double fp = frictionForce(c, 100.0, vt), fm = frictionForce(c, 100.0, -vt);
      EXPECT_EQ(fp, -fm) << "v_t = " << vt;
      EXPECT_LE(fp, 0.0);  // opposes the sliding
      EXPECT_LE(std::fabs(fp), 0.25 * 100.0);
    }
  }
  ContactParams a;
  a.friction = FrictionLaw::Ambrosio;
  a.mu = 0.25;
  // c_d ramps on |v_t| between v_a and v_b.
  EXPECT_EQ(frictionForce(a, 100.0, 0.5e-4), 0.0);
  EXPECT_NEAR(frictionForce(a, 100.0, 0.55e-3), -0.25 * 100.0 * 0.5, 1e-9);
  EXPECT_NEAR(frictionForce(a, 100.0, -0.55e-3), 0.25 * 100.0 * 0.5, 1e-9);
  EXPECT_EQ(frictionForce(a, 100.0, 2e-3), -25.0);
  ContactParams coul;
  coul.friction = FrictionLaw::Coulomb;
  coul.mu = 0.25;
  EXPECT_EQ(frictionForce(coul, 100.0, 1e-9), -25.0);  // plain Coulomb: full at any slip
  EXPECT_EQ(frictionForce(coul, 100.0, 0.0), 0.0);
}

}  // namespace
}  // namespace gimbalsim
