// Bad scene files and bad --set values are refused with a message that names
// the key and where it was given; good ones load as written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "test_util.hpp"

namespace gimbalsim {
namespace {

/// The message of the refusal, or "" if accepted.
std::string refusal(const std::string& yaml, const std::vector<std::string>& sets = {}) {
  try {
    loadSceneText(yaml, "bad.yaml", sets);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

/// The message of a shipped scene's refusal with these sets, or "" if accepted.
std::string sceneRefusal(const std::string& name, const std::vector<std::string>& sets) {
  try {
    test::scene(name, sets);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

const char* kGood = R"(name: t
structure: {base: floating, joint2: clearance}
base:
  mass: 1000
  inertia: [1000, 600, 600]
)";

TEST(Scene, PaperScenesLoadAndWarnAboutTheBaseInertia) {
  for (const char* name : {"paper_ideal", "paper_clearance", "planar_ideal", "planar_clearance"}) {
    const Scene s = loadScene(test::scenePath(name));
    EXPECT_EQ(s.model.name, name);
    ASSERT_EQ(s.warnings.size(), 1u) << name;
    EXPECT_NE(s.warnings[0].find("base.inertia"), std::string::npos);
    EXPECT_NE(s.warnings[0].find("triangle inequality"), std::string::npos);
    EXPECT_NE(s.warnings[0].find(":9:"), std::string::npos) << "line of the key: " << s.warnings[0];
  }
  EXPECT_TRUE(loadSceneText(kGood, "good.yaml").warnings.empty());
}

TEST(Scene, OverridesTakeEffect) {
  const Scene sc = test::scene("paper_clearance", {"sim.duration=2.5", "initial.ecc=[5e-5, -2e-5]",
                                                   "contact.clearance=1e-4", "structure.base=fixed",
                                                   "shaft2.inertia=[0.5, 5, 5, 0.1, 0, 0]"});
  const Model& m = sc.model;
  EXPECT_EQ(sc.run.duration, 2.5);
  EXPECT_EQ(sc.run.initial.ecc[1], Vec2(5e-5, -2e-5));
  EXPECT_NEAR(m.bearing[1].clearance, 1e-4, 1e-15);
  EXPECT_NEAR(m.bearing[1].journal_radius, 9.9e-3, 1e-15);
  EXPECT_FALSE(m.floating_base);
  EXPECT_EQ(m.shaft2.inertia(0, 1), 0.1);
  EXPECT_EQ(m.shaft2.inertia(1, 0), 0.1);
}

TEST(Scene, UnknownKeyInFileNamesKeyAndLine) {
  const std::string e = refusal(std::string(kGood) + "contact:\n  stifness: 3\n");
  EXPECT_NE(e.find("bad.yaml:7:3: unknown key 'contact.stifness'"), std::string::npos) << e;
}

TEST(Scene, WrongTypesAreRefusedWithPosition) {
  std::string e = refusal(std::string(kGood) + "shaft1:\n  mass: heavy\n");
  EXPECT_NE(e.find("bad.yaml:7:3: key 'shaft1.mass': expected a number, got 'heavy'"), std::string::npos) << e;
  e = refusal(kGood, {"shaft1.com=[1, 2]"});
  EXPECT_NE(e.find("--set #1 'shaft1.com=[1, 2]': key 'shaft1.com': expected a list of 3 numbers"),
            std::string::npos)
      << e;
  e = refusal(kGood, {"contact.damping=viscous"});
  EXPECT_NE(e.find("key 'contact.damping': expected one of none | hunt_crossley | lankarani_nikravesh | flores"),
            std::string::npos)
      << e;
  // (pass 42) an empty mapping was skipped and the key ran at its default (tau2 10 N m for a file's 0)
  e = refusal(std::string(kGood) + "torque:\n  tau2: {}\n");
  EXPECT_NE(e.find("bad.yaml:7:3: key 'torque.tau2': expected a number, got a map"), std::string::npos) << e;
  e = refusal(std::string(kGood) + "contact:\n  damping: {}\n");
  EXPECT_NE(e.find("key 'contact.damping': expected one of none | hunt_crossley | lankarani_nikravesh | flores, "
                   "got a map"),
            std::string::npos)
      << e;
  e = refusal(std::string(kGood) + "nope: {}\n");
  EXPECT_NE(e.find("unknown key 'nope'"), std::string::npos) << e;
  EXPECT_EQ(refusal(std::string(kGood) + "contact: {}\n"), "");  // an empty section gives nothing
  // what it got, also when that is nothing (pass 40: '' was refused saying only what was expected)
  e = refusal(kGood, {"contact.damping=''"});
  EXPECT_NE(e.find("key 'contact.damping': expected one of none | hunt_crossley | lankarani_nikravesh | flores, "
                   "got ''"),
            std::string::npos)
      << e;
  e = refusal(kGood, {"contact.damping=[flores]"});
  EXPECT_NE(e.find("key 'contact.damping': expected one of none | hunt_crossley | lankarani_nikravesh | flores, "
                   "got a list"),
            std::string::npos)
      << e;
  e = refusal(kGood, {"sim.step"});
  EXPECT_NE(e.find("--set #1 'sim.step': expected key=value"), std::string::npos) << e;
  e = refusal(kGood, {"no.such=1"});
  EXPECT_NE(e.find("unknown key 'no.such'"), std::string::npos) << e;
}

TEST(Scene, NonPhysicalValuesAreRefused) {
  struct Case {
    std::vector<std::string> sets;
    std::string expect;
  };
  const std::vector<Case> cases = {
      {{"base.mass=0"}, "key 'base.mass': mass must be in [1e-6, 1e9] kg, got 0"},
      {{"shaft1.mass=-3"}, "key 'shaft1.mass': mass must be in [1e-6, 1e9] kg, got -3"},
      // Ranges the arithmetic honours: a body a million km long or a 1e200 kg base would overflow the torques.
      {{"base.mass=1e200"}, "key 'base.mass': mass must be in [1e-6, 1e9] kg, got 1e+200"},
      {{"shaft2.com=[1e200, 0, 0]"}, "key 'shaft2.com': must be in [-1000, 1000]"},
      {{"geometry.joint2_position=[0, 0, -2e3]"}, "key 'geometry.joint2_position': must be in [-1000, 1000]"},
      {{"shaft1.inertia=[1e13, 1e13, 1e13]"},
       "key 'shaft1.inertia': inertia must be symmetric positive definite with principal moments of at least 1e-9 kg "
       "m^2, each entry within 1e12 kg m^2"},
      // A body so light that any contact force overflows its accelerations: a NaN at t = 0, no key named.
      {{"base.inertia=[1e-100, 1e-100, 1e-100]"}, "key 'base.inertia': inertia must be symmetric positive definite "
                                                  "with principal moments of at least 1e-9 kg m^2"},
      {{"shaft2.mass=1e-300"}, "key 'shaft2.mass': mass must be in [1e-6, 1e9] kg, got 1e-300"},
      {{"contact.E_bearing=1e300"}, "key 'contact.E_bearing': must be in [1000, 1e+13]"},
      {{"joint2.contact.E_journal=0.5"}, "key 'joint2.contact.E_journal': must be in [1000, 1e+13]"},
      {{"shaft2.inertia=[1, -1, 1]"}, "key 'shaft2.inertia': inertia must be symmetric positive definite"},
      {{"shaft2.inertia=[[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]"},
       "key 'shaft2.inertia': inertia must be symmetric positive definite"},
      {{"contact.journal_radius=0.011"}, "key 'contact.journal_radius': journal radius (0.011 m, contact.journal_radius) must be < bearing radius (0.01 m, contact.bearing_radius)"},
      {{"contact.journal_radius=0.01"}, "must be < bearing radius"},
      {{"contact.clearance=-1e-4"}, "key 'contact.clearance': clearance must not be negative"},
      {{"contact.restitution=0"}, "key 'contact.restitution': must be in (0, 1], got 0"},
      {{"contact.restitution=1.01"}, "key 'contact.restitution': must be in (0, 1], got 1.01"},
      // (pass 51) a 1e12 m bearing ran on to NaN, the clearance given lost to rounding in R - c
      {{"contact.bearing_radius=1e12", "contact.clearance=5e-4"},
       "key 'contact.bearing_radius': must be in (0, 10], got 1e+12"},
      {{"base.mass=.nan"}, "key 'base.mass': must be finite, got '.nan'"},
      {{"torque.tau1=.inf"}, "key 'torque.tau1': must be finite"},
      {{"torque.tau1=2e6"}, "key 'torque.tau1': must be in [-1e+06, 1e+06]"},
      // YAML drops the blank silently, where every program's flags refuse ' 0.1'
      {{"sim.duration= 0.1"}, "key 'sim.duration': a blank around the value: write key=value"},
      {{"initial.dtheta1=1e300"}, "key 'initial.dtheta1': must be in [-1000, 1000]"},
      {{"initial.theta2=-1e20"}, "key 'initial.theta2': must be in [-1000, 1000]"},
      {{"torque.limit=[1e300, 1]"}, "key 'torque.limit': must be in (0, 1e+06]"},
      // an overflowing direction normalised to a zero vector
      {{"geometry.boresight=[1e200, 1e200, 0]"},
       "key 'geometry.boresight': boresight must be of length at least 1e-12, each component within 1e12"},
      // 1e-400 parses to 0 (or a subnormal): a value nobody wrote
      {{"contact.restitution=1e-400"}, "key 'contact.restitution': '1e-400' underflows a double"},
      {{"initial.theta1=4e-320"}, "key 'initial.theta1': '4e-320' underflows a double"},
      {{"sim.step=1e-3", "sim.output_interval=1.5e-3"}, "key 'sim.output_interval': must be a whole multiple"},
      {{"sim.substep=2e-3"}, "key 'sim.substep': must be in (0, sim.step]"},
      // Adaptive sub-steps cannot cross plain Coulomb's jump: refused, naming both keys and the cure.
      {{"sim.substep_policy=adaptive"},
       "key 'sim.substep_policy': adaptive cannot step over plain Coulomb friction's jump (friction.law=coulomb): "
       "use friction.law=coulomb_stick or ambrosio"},
      // A duration is whole steps, or refused with the nearest valid ones (never rounded).
      {{"sim.step=1e-3", "sim.duration=0.0025"},
       "key 'sim.duration': must be a whole multiple of sim.step (0.001 s), at least one; the nearest: 0.002 or 0.003"},
      // One rule for every whole multiple: half a step off is refused however long the run.
      {{"sim.step=1e-3", "sim.duration=1000.0005"}, "key 'sim.duration': must be a whole multiple of sim.step"},
      {{"sim.step=1e-3", "sim.duration=4e-4"},
       "key 'sim.duration': must be a whole multiple of sim.step (0.001 s), at least one; the shortest: 0.001"},
      {{"initial.ecc=[1e-3, 0]"}, "key 'initial.ecc': initial eccentricity exceeds the radial clearance of joint 2"},
  };
  for (const Case& c : cases) {
    const std::string e = refusal(kGood, c.sets);
    EXPECT_NE(e.find(c.expect), std::string::npos) << "for " << c.sets[0] << " got: " << e;
    EXPECT_NE(e.find("--set #"), std::string::npos) << "must say where: " << e;
  }
  // In a file, the position is the key's line and column.
  const std::string e = refusal(std::string(kGood) + "contact:\n  restitution: 1.5\n");
  EXPECT_NE(e.find("bad.yaml:7:3: key 'contact.restitution': must be in (0, 1], got 1.5"), std::string::npos) << e;
}

TEST(Scene, ShippedDurationsAreWholeSteps) {
  // The shipped scenes and run_paper.sh's sim.duration=0.5 (and 1, 2 of the README) stay valid.
  for (const char* name : {"paper_ideal", "paper_clearance", "planar_ideal", "planar_clearance",
                           "paper_ideal_valid_inertia", "stickslip_clearance", "paper_spatial2", "paper_both_planar",
                           "paper_both_spatial", "planar_spatial2", "paper_planar1", "paper_spatial1"}) {
    for (const char* d : {"sim.duration=0.5", "sim.duration=1", "sim.duration=2"}) {
      EXPECT_NO_THROW(loadScene(test::scenePath(name), {d})) << name << " " << d;
    }
    EXPECT_NO_THROW(loadScene(test::scenePath(name))) << name;
  }
  EXPECT_NO_THROW(loadSceneText(kGood, "good.yaml", {"sim.step=1e-3", "sim.duration=0.3"}));  // 0.3/1e-3 is not exact
}

TEST(Scene, JointKindsAndJoint1BearingDefaultToJoint2s) {
  // The shipped scenes of clearance in either joint load as their names say.
  const std::pair<const char*, const char*> shipped[] = {{"paper_spatial2", "floating_ideal_spatial_friction"},
                                                         {"paper_both_planar", "floating_planar_planar_friction"},
                                                         {"paper_both_spatial", "floating_spatial_spatial_friction"},
                                                         {"planar_spatial2", "floating_ideal_spatial_friction"},
                                                         {"paper_planar1", "floating_planar_ideal_friction"},
                                                         {"paper_spatial1", "floating_spatial_ideal_friction"}};
  for (const auto& [name, variant] : shipped) {
    const Scene s = loadScene(test::scenePath(name));
    EXPECT_EQ(variantName(s.model), variant) << name;
    EXPECT_EQ(s.model.bearing[1].bearing_length, 0.05) << name;
  }
  // Joint 1's bearing is the shared one (contact.*, friction.*), but for its own keys given (old spellings).
  const Scene both = test::scene("paper_clearance", {"structure.joint1=planar", "contact.restitution=0.8",
                                                     "contact1.clearance=2e-4", "friction1.mu=0.1"});
  const ContactParams &c1 = both.model.bearing[0], &c2 = both.model.bearing[1];
  EXPECT_EQ(both.model.joint1_kind, ClearanceKind::Planar);
  EXPECT_EQ(both.model.joint2_kind, ClearanceKind::Planar);  // "clearance" is planar
  EXPECT_EQ(c1.restitution, 0.8);
  EXPECT_EQ(c2.restitution, 0.8);
  EXPECT_NEAR(c1.clearance, 2e-4, 1e-15);
  EXPECT_NEAR(c2.clearance, 5e-4, 1e-15);
  EXPECT_EQ(c1.mu, 0.1);
  EXPECT_EQ(c2.mu, 0.25);
  const double k_ratio = std::sqrt((c1.journal_radius / (c1.journal_radius + c1.bearing_radius)) /
                                   (c2.journal_radius / (c2.journal_radius + c2.bearing_radius)));
  EXPECT_NEAR(c1.K / c2.K, k_ratio, 1e-12) << "joint 1's stiffness follows its own radii (K ~ sqrt(R))";
  EXPECT_NE(c1.K, c2.K);
  EXPECT_EQ(variantName(test::scene("paper_clearance", {"structure.joint2=spatial", "structure.base=fixed",
                                                        "friction.law=none"}).model),
            "fixed_ideal_spatial");
  // Set-valued friction is for a planar joint 2 with an ideal joint 1 only, named at its key.
  std::string e = refusal(kGood, {"structure.joint2=spatial", "friction.law=coulomb_stick"});
  EXPECT_NE(e.find("friction.law"), std::string::npos) << e;
  EXPECT_NE(e.find("planar joint 2 with an ideal joint 1"), std::string::npos) << e;
  e = refusal(kGood, {"structure.joint1=planar", "friction1.law=coulomb_stick"});
  EXPECT_NE(e.find("friction1.law"), std::string::npos) << e;
  // Joint 1's bearing is checked when joint 1 has clearance, naming its keys.
  e = refusal(kGood, {"structure.joint1=spatial", "contact1.journal_radius=0.02"});
  EXPECT_NE(e.find("contact1.journal_radius"), std::string::npos) << e;
  EXPECT_EQ(refusal(kGood, {"contact1.journal_radius=0.02"}), "") << "ideal joint 1: its bearing's radii are not used";
  e = refusal(kGood, {"contact1.restitution=2"});
  EXPECT_NE(e.find("contact1.restitution"), std::string::npos) << "a bad value is refused, used or not: " << e;
  // A bad shared value is refused once, at its key, not again as joint 1's.
  e = refusal(kGood, {"structure.joint1=planar", "contact.restitution=2"});
  EXPECT_NE(e.find("contact.restitution"), std::string::npos) << e;
  EXPECT_EQ(e.find("contact1.restitution"), std::string::npos) << e;
  e = refusal(kGood, {"structure.joint1=planar", "contact1.restitution=2"});
  EXPECT_NE(e.find("contact1.restitution"), std::string::npos) << e;
  e = refusal(kGood, {"structure.joint2=spatial", "contact.bearing_length=0"});
  EXPECT_NE(e.find("contact.bearing_length"), std::string::npos) << e;
  // A bearing too short for the end-plane model (1e-300 m let a journal turn over): refused, naming the key.
  e = refusal(kGood, {"structure.joint2=spatial", "contact.clearance=1e-4", "joint2.contact.bearing_length=1e-300"});
  EXPECT_NE(e.find("key 'joint2.contact.bearing_length': a spatial bearing must be at least 4 clearances long"),
            std::string::npos)
      << e;
  EXPECT_EQ(refusal(kGood, {"structure.joint2=spatial", "contact.clearance=1e-4", "contact.bearing_length=4e-4"}),
            "");
  // Too long or too stiff for the arithmetic (1e300 ran on to NaN "in base_x", naming no key).
  e = refusal(kGood, {"structure.joint2=spatial", "contact.bearing_length=1e300"});
  EXPECT_NE(e.find("key 'contact.bearing_length': must be in (0, 10], got 1e+300"), std::string::npos) << e;
  e = refusal(kGood, {"structure.joint2=spatial", "contact.stiffness_scale=1e300"});
  EXPECT_NE(e.find("key 'contact.stiffness_scale': must be in (0, 1e+06], got 1e+300"), std::string::npos) << e;
  // A planar bearing has no length to check: its contact is in one plane.
  EXPECT_EQ(refusal(kGood, {"structure.joint2=planar", "contact.bearing_length=1e-300"}), "");
  // (pass 55) flores at c_e = 1e-6 ended on a velocity limit at the first impact, 1e-300 in NaN: refused at the
  // key that gave it; the other laws' chi stays bounded, and 1e-4 is flores' own smallest.
  e = refusal(kGood, {"structure.joint2=planar", "contact.damping=flores", "contact.restitution=1e-6"});
  EXPECT_NE(e.find("key 'contact.restitution': with contact.damping flores must be >= 1e-04, got 1e-06"),
            std::string::npos)
      << e;
  e = refusal(kGood, {"structure.joint2=planar", "contact.damping=flores", "joint2.contact.restitution=1e-300"});
  EXPECT_NE(e.find("key 'joint2.contact.restitution': with contact.damping flores"), std::string::npos) << e;
  EXPECT_EQ(refusal(kGood, {"structure.joint2=planar", "contact.damping=flores", "contact.restitution=1e-4"}), "");
  EXPECT_EQ(refusal(kGood, {"structure.joint2=planar", "contact.restitution=1e-6"}), "");
  e = refusal(kGood, {"structure.joint1=tilted"});
  EXPECT_NE(e.find("structure.joint1"), std::string::npos) << e;
}

TEST(Scene, BothJointsAreNamedAlike) {
  // A joint's own key overrides the shared one for that joint only.
  const Scene both = test::scene("paper_both_planar", {"joint2.contact.clearance=3e-4", "joint1.friction.mu=0.1",
                                                       "contact.restitution=0.8", "joint2.contact.restitution=0.7"});
  const ContactParams &c1 = both.model.bearing[0], &c2 = both.model.bearing[1];
  EXPECT_NEAR(c1.clearance, 5e-4, 1e-15);
  EXPECT_NEAR(c2.clearance, 3e-4, 1e-15);
  EXPECT_EQ(c1.mu, 0.1);
  EXPECT_EQ(c2.mu, 0.25);
  EXPECT_EQ(c1.restitution, 0.8);
  EXPECT_EQ(c2.restitution, 0.7);
  // The old spellings are the same keys: the same Model, and both at once in a file is a key given twice.
  const Scene old = test::scene("paper_both_planar", {"contact1.clearance=2e-4", "friction1.mu=0.1"});
  const Scene now = test::scene("paper_both_planar", {"joint1.contact.clearance=2e-4", "joint1.friction.mu=0.1"});
  EXPECT_EQ(old.model.bearing[0].journal_radius, now.model.bearing[0].journal_radius);
  EXPECT_EQ(old.model.bearing[0].K, now.model.bearing[0].K);
  EXPECT_EQ(old.model.bearing[0].mu, now.model.bearing[0].mu);
  std::string e = refusal(std::string(kGood) + "friction1:\n  mu: 0.1\njoint1:\n  friction:\n    mu: 0.2\n");
  EXPECT_NE(e.find("given twice"), std::string::npos) << e;
  // A refusal names the key as the user spelled it, and the joint's bearing it acts on.
  e = refusal(kGood, {"structure.joint1=planar", "joint1.contact.journal_radius=0.02"});
  EXPECT_NE(e.find("key 'joint1.contact.journal_radius': journal radius (0.02 m, joint1.contact.journal_radius) must be < bearing radius"),
            std::string::npos)
      << e;
  // A joint's own bearing radius below the shared journal radius is the joint's key's refusal, said once
  // (it was blamed on contact.journal_radius, with initial.ecc's "exceeds the clearance" after it).
  e = refusal(kGood, {"joint2.contact.bearing_radius=0.009"});
  EXPECT_NE(e.find("key 'joint2.contact.bearing_radius': journal radius (0.0095 m, contact.journal_radius) must be < "
                   "bearing radius (0.009 m, joint2.contact.bearing_radius)"),
            std::string::npos)
      << e;
  EXPECT_EQ(e.find("initial.ecc"), std::string::npos) << e;
  // A sub-key of contact1 with no counterpart stays unknown.
  EXPECT_NE(refusal(kGood, {"contact1.bogus=1"}).find("unknown key 'contact1.bogus'"), std::string::npos);
  // A joint's own bearing keys for an ideal joint are not used: accepted with a warning naming the key.
  const Scene ideal = test::scene("paper_clearance", {"joint1.contact.clearance=1e-4"});
  const auto unused = std::find_if(ideal.warnings.begin(), ideal.warnings.end(), [](const std::string& w) {
    return w.find("key 'joint1.contact.clearance': joint 1 is ideal") != std::string::npos;
  });
  EXPECT_NE(unused, ideal.warnings.end()) << "warnings: " << ideal.warnings.size();
}

TEST(Scene, EachJournalStartsWhereItsOwnKeySays) {
  // initial.ecc is both journals' unless a joint gives its own; each acts on its joint's state.
  const Scene planar1 = test::scene("paper_planar1", {"initial.ecc=[1e-4, -5e-5]"});
  using V1 = GIMBALSIM_SHAPE(true, Planar, Ideal, true);
  const State<V1> s1 = initialState<V1>(planar1.run.initial);
  EXPECT_EQ(s1.q(State<V1>::QJ + V1::G1), 1e-4) << "paper_planar1's journal is joint 1's";
  EXPECT_EQ(s1.q(State<V1>::QJ + V1::G1 + 1), -5e-5);
  const Scene both = test::scene("paper_both_planar", {"initial.ecc=[1e-4, 0]", "initial.ecc2=[0, 2e-4]"});
  using V2 = GIMBALSIM_SHAPE(true, Planar, Planar, true);
  const State<V2> s2 = initialState<V2>(both.run.initial);
  EXPECT_EQ(s2.q(State<V2>::QJ + V2::G1), 1e-4);
  EXPECT_EQ(s2.q(State<V2>::QJ + V2::G2), 0.0);
  EXPECT_EQ(s2.q(State<V2>::QJ + V2::G2 + 1), 2e-4);
  // Checked against the bearing it acts on, named as given.
  std::string e = refusal(kGood, {"structure.joint1=planar", "joint1.contact.clearance=1e-4", "initial.ecc1=[2e-4, 0]"});
  EXPECT_NE(e.find("key 'initial.ecc1': initial eccentricity exceeds the radial clearance of joint 1"),
            std::string::npos)
      << e;
  e = refusal(kGood, {"structure.joint1=planar", "joint1.contact.clearance=1e-4", "initial.ecc=[2e-4, 0]"});
  EXPECT_NE(e.find("key 'initial.ecc': initial eccentricity exceeds the radial clearance of joint 1"), std::string::npos)
      << e;
  // An eccentricity that cannot act is accepted with a warning naming its key
  // (a scene's ideal twin keeps its values); zero says nothing.
  auto warned = [](const Scene& sc, const std::string& what) {
    return std::count_if(sc.warnings.begin(), sc.warnings.end(),
                         [&](const std::string& w) { return w.find(what) != std::string::npos; });
  };
  const Scene own = loadSceneText(kGood, "good.yaml", {"initial.ecc1=[1e-4, 0]"});
  EXPECT_EQ(warned(own, "key 'initial.ecc1': joint 1 is ideal (structure.joint1): its journal has no eccentricity"), 1);
  const Scene twin = loadSceneText(kGood, "good.yaml", {"structure.joint2=ideal", "initial.ecc=[1e-4, 0]"});
  EXPECT_EQ(warned(twin, "key 'initial.ecc': no joint has clearance"), 1) << "named once";
  EXPECT_EQ(warned(test::scene("paper_planar1"), "initial.ecc"), 0) << "its [0, 0] says nothing";
  EXPECT_NO_THROW(test::scene("paper_planar1", {"initial.ecc=[0, 0]", "initial.ecc2=[0, 0]"}));
}

TEST(Scene, ASpatialJournalStartsTiltedWhereItsKeySays) {
  // initial.tilt2 = [alpha, beta] acts on joint 2's tilt coordinates (before it, every
  // journal started untilted and a budget could not disperse the tilt).
  const Scene tilted = test::scene("paper_spatial2", {"initial.tilt2=[1e-3, -2e-3]"});
  using V = GIMBALSIM_SHAPE(true, Ideal, Spatial, true);
  const State<V> s = initialState<V>(tilted.run.initial);
  EXPECT_EQ(s.q(State<V>::QJ + V::G2 + 2), 1e-3) << "alpha";
  EXPECT_EQ(s.q(State<V>::QJ + V::G2 + 3), -2e-3) << "beta";
  // Both ends (at +-L/2, L = 0.05 m) inside the 0.5 mm clearance with the centre's offset: the
  // offsets add as vectors, so a tilt across the eccentricity fits where one along it does not.
  EXPECT_NO_THROW(test::scene("paper_spatial2", {"initial.ecc2=[4e-4, 0]", "initial.tilt2=[5e-3, 0]"}));
  std::string e = sceneRefusal("paper_spatial2", {"initial.ecc2=[4e-4, 0]", "initial.tilt2=[0, 5e-3]"});
  EXPECT_NE(e.find("key 'initial.tilt2': joint 2's journal would start with its end at +L/2 0.000525"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("beyond the clearance of 0.0005"), std::string::npos) << e;
  EXPECT_NE(e.find(" m (with initial.ecc2 and contact.bearing_length): both ends must start inside"),
            std::string::npos)
      << e;
  e = sceneRefusal("paper_spatial2", {"initial.tilt2=[0, 0.025]"});  // 0.025 m x tan(0.025) > 0.5 mm
  EXPECT_NE(e.find("key 'initial.tilt2': joint 2's journal would start with its end at -L/2"), std::string::npos)
      << e;
  e = sceneRefusal("paper_spatial2", {"initial.tilt2=[0.6, 0]"});
  EXPECT_NE(e.find("key 'initial.tilt2'"), std::string::npos) << e;
  EXPECT_NE(e.find("in [-0.5, 0.5]"), std::string::npos) << e;
  // A journal that cannot tilt: accepted with a warning naming the key, as an ideal joint's eccentricity.
  const Scene planar = test::scene("paper_clearance", {"initial.tilt2=[1e-3, 0]"});
  EXPECT_EQ(std::count_if(planar.warnings.begin(), planar.warnings.end(),
                          [](const std::string& w) {
                            return w.find("key 'initial.tilt2': joint 2's bearing is not spatial") !=
                                   std::string::npos;
                          }),
            1);
}

TEST(Scene, ValuesListEveryOwnKeyGivenEvenWhereItEqualsTheSharedOne) {
  // A scene rebuilt from its values with the shared key changed (a sweep's
  // sample) must keep a joint's own value: listed only where it differed,
  // initial.ecc2 = initial.ecc was dropped and the new shared value reached joint 2.
  const auto values = [](const Scene& sc) { return sceneTable().values(sc); };
  const auto has = [](const std::vector<std::string>& v, const std::string& kv) {
    return std::find(v.begin(), v.end(), kv) != v.end();
  };
  const Scene given = test::scene("paper_both_planar", {"initial.ecc=[0, 0]", "initial.ecc2=[0, 0]",
                                                        "joint2.contact.clearance=5e-4", "joint1.friction.mu=0.25"});
  const std::vector<std::string> v = values(given);
  EXPECT_TRUE(has(v, "initial.ecc2=[0, 0]"));
  EXPECT_FALSE(std::any_of(v.begin(), v.end(), [](const std::string& kv) { return kv.rfind("initial.ecc1=", 0) == 0; }));
  EXPECT_TRUE(std::any_of(v.begin(), v.end(), [](const std::string& kv) {
    return kv.rfind("joint2.contact.journal_radius=", 0) == 0;  // the clearance, as the radius it sets
  }));
  EXPECT_TRUE(std::any_of(v.begin(), v.end(), [](const std::string& kv) { return kv.rfind("joint1.friction.mu=", 0) == 0; }));
  std::vector<std::string> rebuilt = v;
  rebuilt.insert(rebuilt.end(), {"initial.ecc=[1e-4, 0]", "contact.clearance=3e-4", "friction.mu=0.1"});
  const Scene sample = loadSceneText("", "values", rebuilt, v.size());  // v: the printed values
  EXPECT_EQ(sample.run.initial.ecc[0], Vec2(1e-4, 0.0)) << "joint 1 follows the shared key";
  EXPECT_EQ(sample.run.initial.ecc[1], Vec2(0.0, 0.0)) << "joint 2 keeps its own";
  EXPECT_NEAR(sample.model.bearing[0].clearance, 3e-4, 1e-15);
  EXPECT_NEAR(sample.model.bearing[1].clearance, 5e-4, 1e-15);
  EXPECT_EQ(sample.model.bearing[0].mu, 0.25);
  EXPECT_EQ(sample.model.bearing[1].mu, 0.1);
  // A scene that gives no own key lists none.
  const std::vector<std::string> plain = values(test::scene("paper_both_planar"));
  EXPECT_FALSE(std::any_of(plain.begin(), plain.end(), [](const std::string& kv) {
    return kv.rfind("joint", 0) == 0 || kv.rfind("initial.ecc1", 0) == 0 || kv.rfind("initial.ecc2", 0) == 0;
  }));
}

TEST(Scene, EveryProblemIsReportedAtOnce) {
  const std::string e = refusal(kGood, {"base.mass=-1", "contact.restitution=2"});
  EXPECT_NE(e.find("base.mass"), std::string::npos);
  EXPECT_NE(e.find("contact.restitution"), std::string::npos);
}

TEST(Scene, AModelWhoseFirstRowIsNotFiniteIsRefusedNotRun) {
  // (pass 39) each key within its range, together a mass matrix no double solves: NaN accelerations at t = 0,
  // and the run "stopped" at t = 0 with no good row (exit 3) instead of being refused
  const std::vector<std::string> heavy = {"shaft2.mass=1e9", "shaft2.com=[1000, 0, 0]"};
  for (const char* name : {"paper_spatial2", "paper_both_spatial"}) {
    EXPECT_NE(sceneRefusal(name, heavy).find("the model's first row is not finite"), std::string::npos) << name;
  }
  // (pass 40) a key for a sweep's status (refused:<key>, not "refused:"): the body carrying the most inertia
  try {
    test::scene("paper_spatial2", heavy);
    ADD_FAILURE() << "must throw";
  } catch (const SceneError& e) {
    ASSERT_EQ(e.details().size(), 1u);
    EXPECT_EQ(e.details()[0].key, "shaft2.mass");
  }
  // the same bodies an order lighter, and on the planar bearing, start (and stop on a named check later)
  EXPECT_EQ(sceneRefusal("paper_spatial2", {"shaft2.mass=1e8", "shaft2.com=[1000, 0, 0]"}), "");
  EXPECT_EQ(sceneRefusal("paper_clearance", heavy), "");
}

TEST(Scene, BrokenYamlAndMissingFile) {
  EXPECT_NE(refusal("base: [1, 2\n").find("bad.yaml:"), std::string::npos);
  try {
    loadScene("/nonexistent/scene.yaml");
    FAIL() << "must throw";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/scene.yaml: cannot open"), std::string::npos);
  }
}

}  // namespace
}  // namespace gimbalsim
