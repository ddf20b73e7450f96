// A State is a checkpoint: copy it at any point of a run, step the copy with
// a fresh workspace (Data), and it reproduces the original run bit for bit.
// Checked for every variant and both sub-step policies, at the hard places:
// mid-impact, mid-stick (coulomb_stick), and before the first contact (where
// the adaptive policy has not chosen a sub-step yet).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>

#include "gimbalsim/dynamics/simulate.hpp"
#include "test_util.hpp"

namespace gimbalsim {
namespace {

template <class V>
bool sameBits(const State<V>& a, const State<V>& b) {
  auto eq = [](double x, double y) { return std::memcmp(&x, &y, sizeof x) == 0; };
  for (int i = 0; i < V::NQ; ++i) {
    if (!eq(a.q(i), b.q(i))) return false;
  }
  for (int i = 0; i < V::NV; ++i) {
    if (!eq(a.v(i), b.v(i))) return false;
  }
  return eq(a.t, b.t) && a.in_contact == b.in_contact &&
         std::memcmp(a.v0.data(), b.v0.data(), sizeof a.v0) == 0 && a.friction_mode == b.friction_mode &&
         eq(a.vt_floor, b.vt_floor) && eq(a.h_next, b.h_next);
}

/// Runs sc until `at` holds (at most t_max), copies the State, then steps the
/// original (its warm Data) and the copy (a fresh Data) side by side.
template <class V>
void expectCheckpointResumes(const Scene& sc, const std::function<bool(const State<V>&)>& at, double t_max,
                             int steps_after) {
  const Model& m = sc.model;
  const Input u{sc.run.torque};
  Data<V> d(m);
  State<V> s = initialState<V>(sc.run.initial);
  long long k = 0;
  while (!at(s)) {
    ASSERT_LT(s.t, t_max) << "the checkpoint condition never held";
    ASSERT_TRUE(advanceSteps(m, d, s, u, k, k + 1).ok());
    ++k;
  }
  State<V> copy = s;
  Data<V> fresh(m);
  for (int j = 0; j < steps_after; ++j, ++k) {
    const StepResult a = advanceSteps(m, d, s, u, k, k + 1);
    const StepResult b = advanceSteps(m, fresh, copy, u, k, k + 1);
    ASSERT_EQ(a.status, StepStatus::Ok);
    ASSERT_EQ(b.status, StepStatus::Ok);
    ASSERT_TRUE(sameBits(s, copy)) << "diverged " << j + 1 << " steps after the checkpoint at t = " << s.t;
  }
  if constexpr (V::kContact) EXPECT_GT(d.stats.impacts + fresh.stats.impacts, 0);
}

std::vector<std::string> variantSets(bool floating, bool clearance, bool friction, bool adaptive) {
  std::vector<std::string> sets = {"friction.law=" + std::string(friction ? "coulomb_stick" : "none")};
  if (!floating) sets.push_back("structure.base=fixed");
  if (!clearance) sets.push_back("structure.joint2=ideal");
  if (adaptive) {
    sets.insert(sets.end(), {"sim.substep_policy=adaptive", "sim.substep_tol=1e-8"});
  }
  return sets;
}

template <class V>
Scene sceneOf(bool adaptive) {
  const Scene sc =
      test::scene("paper_clearance", variantSets(V::kFloating, V::kContact, V::kFriction, adaptive));
  bool match = false;
  dispatchVariant(sc.model, [&](auto tag) { match = std::is_same_v<decltype(tag), V>; });
  EXPECT_TRUE(match) << "the scene does not load as the variant under test";
  return sc;
}

template <class V>
void checkVariant(bool adaptive) {
  SCOPED_TRACE(std::string(adaptive ? "adaptive" : "fixed") + " policy, " + variantName(sceneOf<V>(adaptive).model));
  const Scene sc = sceneOf<V>(adaptive);
  if constexpr (!V::kContact) {
    expectCheckpointResumes<V>(sc, [](const State<V>& s) { return s.t >= 0.25; }, 1.0, 200);
  } else {
    const Model& m = sc.model;
    // Just before the first contact: the next step is the first to sub-step
    // (the gap may close within it) and no sub-step has been chosen yet.
    expectCheckpointResumes<V>(
        sc,
        [&](const State<V>& s) {
          const Gap g = clearanceGap<V>(m, s.q, s.v);
          return s.h_next == 0.0 && g.delta + std::fmax(g.rate, 0.0) * m.integrator.step > 0.0;
        },
        0.1, 300);
    // Mid-impact: in contact and penetrating, soon after an onset.
    expectCheckpointResumes<V>(
        sc, [&](const State<V>& s) { return s.in_contact[0] && clearanceGap<V>(m, s.q, s.v).delta > 1e-7; }, 2.0, 100);
    if constexpr (V::kFriction) {
      // Mid-stick: in contact with the journal sticking (coulomb_stick mode 0).
      expectCheckpointResumes<V>(
          sc, [&](const State<V>& s) { return s.in_contact[0] && s.friction_mode == 0 && s.t > 0.1; }, 4.0, 100);
    }
  }
}

class Checkpoint : public ::testing::TestWithParam<bool> {};

TEST_P(Checkpoint, FixedIdeal) { checkVariant<FixedIdeal>(GetParam()); }
TEST_P(Checkpoint, FixedClearance) { checkVariant<FixedClearance>(GetParam()); }
TEST_P(Checkpoint, FixedClearanceFriction) { checkVariant<FixedClearanceFriction>(GetParam()); }
TEST_P(Checkpoint, FloatingIdeal) { checkVariant<FloatingIdeal>(GetParam()); }
TEST_P(Checkpoint, FloatingClearance) { checkVariant<FloatingClearance>(GetParam()); }
TEST_P(Checkpoint, FloatingClearanceFriction) { checkVariant<FloatingClearanceFriction>(GetParam()); }

/// Mid-impact at each contact end in turn (its side in contact, penetrating):
/// the copy resumes bit for bit, whichever end is mid-impact.
template <class V>
void checkEveryEnd(const Scene& sc) {
  const Model& m = sc.model;
  ASSERT_EQ(variantName(m), shapeName(V::kFloating, V::kKind1, V::kKind2, V::kFriction));
  for (int e = 0; e < V::NC; ++e) {
    SCOPED_TRACE(variantName(m) + ", end " + std::to_string(e) + " mid-impact");
    expectCheckpointResumes<V>(
        sc, [&](const State<V>& s) { return s.in_contact[e] && endGap<V>(m, e, s.q, s.v).delta > 1e-7; }, 3.0, 100);
  }
}

TEST(CheckpointEnds, BothJointsSpatial) {
  using CK = ClearanceKind;
  checkEveryEnd<Variant<true, CK::Spatial, CK::Spatial, true>>(test::scene("paper_both_spatial"));
}

TEST(CheckpointEnds, PlanarJoint1SpatialJoint2OnAFixedBase) {
  using CK = ClearanceKind;
  checkEveryEnd<Variant<false, CK::Planar, CK::Spatial, true>>(
      test::scene("paper_spatial2", {"structure.base=fixed", "structure.joint1=planar", "friction.law=ambrosio",
                                     "sim.substep_policy=adaptive", "sim.substep_tol=1e-8"}));
}

// A State carries each contact end's memory (two spatial joints: four ends),
// and a copy carries all of it.
TEST(CheckpointMemory, StateKeepsTheMemoryOfEveryContactEnd) {
  using CK = ClearanceKind;
  using V = Variant<true, CK::Spatial, CK::Spatial, false>;
  State<V> s;
  ASSERT_EQ(s.in_contact.size(), 4u);
  ASSERT_EQ(s.v0.size(), 4u);
  EXPECT_FALSE(s.anyInContact());
  s.in_contact[3] = true;
  s.v0[3] = 0.02;
  s.v0[1] = -0.01;
  const State<V> copy = s;
  EXPECT_TRUE(sameBits(s, copy));
  EXPECT_TRUE(copy.anyInContact());
  EXPECT_EQ(copy.v0[1], -0.01);
  State<Variant<false, CK::Planar, CK::Ideal, false>> one;
  EXPECT_EQ(one.in_contact.size(), 1u);
  EXPECT_EQ((State<FixedIdeal>{}.in_contact.size()), 0u);
}

INSTANTIATE_TEST_SUITE_P(Policies, Checkpoint, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& p) { return p.param ? "Adaptive" : "Fixed"; });

}  // namespace
}  // namespace gimbalsim
