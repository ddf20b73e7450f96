// A --set that the scene's joints leave idle is told apart from one that acts (Scene::idle_sets): the study
// programs refuse one idle in every run. A scene file's own idle keys (an ideal twin's bearing) say nothing.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "test_util.hpp"

namespace gimbalsim {
namespace {

int idleNumber(const Scene& s, const std::string& key) {
  for (const auto& [number, why] : s.idle_sets) {
    if (why.find("key '" + key + "'") != std::string::npos) return number;
  }
  return 0;
}

TEST(IdleKeys, EachSetTheJointsLeaveIdleIsNumberedWithWhy) {
  // paper_clearance: joint 1 ideal, joint 2 planar.
  const Scene s = test::scene("paper_clearance", {"contact.restitution=0.5", "joint1.friction.mu=0.2",
                                                  "initial.tilt2=[1e-3, 0]", "contact.bearing_length=0.1",
                                                  "joint2.contact.bearing_length=0.1", "initial.ecc1=[1e-5, 0]"});
  EXPECT_EQ(idleNumber(s, "contact.restitution"), 0) << "acts on joint 2";
  EXPECT_EQ(idleNumber(s, "joint1.friction.mu"), 2);
  EXPECT_EQ(idleNumber(s, "initial.tilt2"), 3);
  EXPECT_EQ(idleNumber(s, "contact.bearing_length"), 4);
  EXPECT_EQ(idleNumber(s, "joint2.contact.bearing_length"), 5);
  EXPECT_EQ(idleNumber(s, "initial.ecc1"), 6);
  EXPECT_EQ(s.idle_sets.size(), 5u);
  // An alias is named as spelled; a tilting bearing reads its length.
  EXPECT_EQ(idleNumber(test::scene("paper_clearance", {"friction1.mu=0.2"}), "friction1.mu"), 1);
  EXPECT_TRUE(test::scene("paper_spatial2", {"contact.bearing_length=0.1"}).idle_sets.empty());
}

// (pass 91) a fixed base never moves: a --set of its mass or inertia ran with no word, the run unchanged
TEST(IdleKeys, AFixedBaseLeavesItsBodyJoint1PlaceAndMomentumTolIdle) {
  const std::vector<std::string> sets{"structure.base=fixed", "base.mass=500", "base.inertia=[10, 10, 10]",
                                      "geometry.joint1_position=[0, 0, 1]", "sim.momentum_tol=1e-6"};
  const Scene fixed = test::scene("paper_clearance", sets);
  for (int k = 2; k <= 5; ++k) {
    EXPECT_EQ(idleNumber(fixed, sets[k - 1].substr(0, sets[k - 1].find('='))), k) << sets[k - 1];
  }
  EXPECT_EQ(fixed.idle_sets.size(), 4u);
  EXPECT_NE(fixed.idle_sets[0].second.find("structure.base is fixed"), std::string::npos) << fixed.idle_sets[0].second;
  std::vector<std::string> floating = sets;
  floating[0] = "structure.base=floating";
  EXPECT_TRUE(test::scene("paper_clearance", floating).idle_sets.empty());
  EXPECT_TRUE(test::scene("paper_clearance", {"structure.base=fixed"}).idle_sets.empty())
      << "the file's own say nothing";
}

TEST(IdleKeys, BothJointsIdealLeaveEveryBearingKeyIdleButOnlyASetIsSaid) {
  const Scene file_only = test::scene("paper_ideal");
  EXPECT_TRUE(file_only.idle_sets.empty());
  EXPECT_EQ(file_only.warnings.size(), 1u) << "the base inertia's only";
  // A clearance given as clearance replaces the file's journal radius: said once, as given.
  const Scene s = test::scene("paper_ideal", {"sim.step=1e-3", "contact.clearance=1e-4", "friction.law=none"});
  ASSERT_EQ(s.idle_sets.size(), 2u);
  EXPECT_EQ(idleNumber(s, "contact.clearance"), 2);
  EXPECT_NE(s.idle_sets[0].second.find("no joint has clearance"), std::string::npos) << s.idle_sets[0].second;
  EXPECT_EQ(idleNumber(s, "friction.law"), 3);
}

TEST(IdleKeys, ASharedSetEveryJointWithABearingOverridesIsIdle) {
  // paper_clearance's one bearing (joint 2) takes its own radius: the shared one acts nowhere, either spelling.
  for (const char* own : {"joint2.contact.journal_radius=0.0095", "joint2.contact.clearance=3e-4"}) {
    const Scene s = test::scene("paper_clearance", {"contact.clearance=2e-4", own});
    EXPECT_EQ(idleNumber(s, "contact.clearance"), 1) << own;
    EXPECT_EQ(s.idle_sets.size(), 1u) << own;
  }
  const Scene ecc = test::scene("paper_clearance", {"initial.ecc=[1e-5, 0]", "initial.ecc2=[2e-5, 0]"});
  EXPECT_EQ(idleNumber(ecc, "initial.ecc"), 1);
  const Scene mu = test::scene("paper_both_planar", {"friction.mu=0.3", "joint1.friction.mu=0.1",
                                                     "joint2.friction.mu=0.2"});
  EXPECT_EQ(idleNumber(mu, "friction.mu"), 1);
  ASSERT_EQ(mu.idle_sets.size(), 1u);
  EXPECT_NE(mu.idle_sets[0].second.find("joint1.friction.mu, joint2.friction.mu"), std::string::npos)
      << mu.idle_sets[0].second;
  // One joint taking the shared value is enough for it to act; a length acts on spatial joints only.
  EXPECT_TRUE(test::scene("paper_both_planar", {"friction.mu=0.3", "joint2.friction.mu=0.2"}).idle_sets.empty());
  EXPECT_TRUE(test::scene("paper_both_spatial", {"initial.ecc=[1e-5, 0]", "initial.ecc2=[2e-5, 0]"})
                  .idle_sets.empty());
  EXPECT_EQ(idleNumber(test::scene("paper_spatial2", {"contact.bearing_length=0.1",
                                                      "joint2.contact.bearing_length=0.2"}),
                       "contact.bearing_length"),
            1);
  // The file's own shared value overridden by a --set is the override the user asked for: nothing said.
  EXPECT_TRUE(test::scene("paper_clearance", {"joint2.contact.clearance=3e-4"}).idle_sets.empty());
}

// (pass 88) friction.mu under friction.law none, and v_a, v_b under coulomb, ran recorded as applied.
TEST(IdleKeys, AFrictionKeyTheBearingsLawDoesNotReadIsIdle) {
  const Scene none = test::scene("paper_clearance", {"friction.law=none", "friction.mu=3"});
  EXPECT_EQ(idleNumber(none, "friction.mu"), 2);
  ASSERT_EQ(none.idle_sets.size(), 1u);
  EXPECT_NE(none.idle_sets[0].second.find("joint 2: its friction.law is none"), std::string::npos)
      << none.idle_sets[0].second;
  const Scene coulomb = test::scene("paper_clearance", {"friction.v_b=0.3", "friction.v_a=0.1"});
  EXPECT_EQ(idleNumber(coulomb, "friction.v_b"), 1);
  EXPECT_EQ(idleNumber(coulomb, "friction.v_a"), 2);
  EXPECT_EQ(idleNumber(test::scene("paper_clearance", {"friction.mu=0", "friction.law=ambrosio"}), "friction.law"), 2);
  EXPECT_EQ(idleNumber(test::scene("paper_both_planar", {"joint1.friction.law=none", "joint1.friction.mu=0.3"}),
                       "joint1.friction.mu"),
            2);
  // Read: Ambrosio's thresholds under ambrosio, a law with friction, a shared key one joint still reads.
  EXPECT_TRUE(test::scene("paper_clearance", {"friction.law=ambrosio", "friction.v_b=0.3"}).idle_sets.empty());
  EXPECT_TRUE(test::scene("paper_clearance", {"friction.law=coulomb_stick", "friction.mu=0.3"}).idle_sets.empty());
  EXPECT_TRUE(test::scene("paper_both_planar", {"joint1.friction.law=none", "friction.mu=0.3"}).idle_sets.empty());
}

}  // namespace
}  // namespace gimbalsim
