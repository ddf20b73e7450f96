// Clearance in either joint, planar or spatial, through the integrator
// (docs/MODEL.md 2.7 and 8): the physics page's checks on the variants
// instantiated directly. Each end's contact is located and remembered on its
// own; these runs hold impacts at both ends of a spatial bearing.
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>
#include <cmath>
#include <cstdio>

#include "test_util.hpp"

namespace gimbalsim {
namespace {

using CK = ClearanceKind;
template <CK K1, CK K2, bool Floating = true>
using Shape = Variant<Floating, K1, K2, true>;

/// The scene with these joint kinds, joint 1's bearing the same as joint 2's.
Scene withKinds(Scene sc, CK k1, CK k2) {
  sc.model.bearing[0] = sc.model.bearing[1];
  sc.model.joint1_kind = k1;
  sc.model.joint2_kind = k2;
  sc.model.finalize();
  return sc;
}

/// Steps sc for T seconds from its initial state; calls f(s, d) after each step.
template <class V, class F>
State<V> runFor(const Scene& sc, double T, Data<V>& d, F&& f) {
  const Model& m = sc.model;
  const Input u{sc.run.torque};
  State<V> s = initialState<V>(sc.run.initial);
  const long long n = std::llround(T / m.integrator.step);
  for (long long k = 1; k <= n; ++k) {
    const StepResult r = step(m, d, s, u);
    EXPECT_EQ(r.status, StepStatus::Ok) << "t = " << s.t << ": " << describe(r.status);
    if (!r.ok()) break;
    s.t = static_cast<double>(k) * m.integrator.step;
    f(s, d);
  }
  return s;
}

/// The joint-2 group's coordinates of a spatial variant: p_x, p_y, alpha, beta, theta.
template <class V>
Eigen::Matrix<double, 5, 1> group2(const State<V>& s) {
  return s.q.template segment<5>(State<V>::QJ + V::G2);
}

// Check 1: in the planar scene (every axis along base z, every CoM in the
// base plane) a spatial joint 2 started centred and untilted stays untilted
// by symmetry, and the run is the planar-clearance run to the integrator's
// accuracy: with the regularised friction law to 1e-9; with plain Coulomb
// (whose jump makes the run sensitive to the located switch times) within the
// planar run's own change when the sub-step is halved, plus the spatial run's
// own spread under a round-off-sized change (1e-15 m of initial
// eccentricity). That spread is not small: the spatial Coulomb run moves by
// 4e-8 to 1.7e-7 m of final eccentricity under it (the planar run by 3e-10),
// so round-off alone, e.g. a different but equally exact solve of M vdot = b,
// moves the gap by as much as the margin the first two terms leave.
TEST(SpatialStepping, PlanarSceneSpatialJointStaysUntiltedAndEqualsPlanar) {
  using VP = Shape<CK::Ideal, CK::Planar>;
  using VS = Shape<CK::Ideal, CK::Spatial>;
  struct Result {
    double theta1, theta2, ecc_x, ecc_y;
  };
  auto planarRun = [](const Scene& sc, long long& impacts) {
    Data<VP> d(sc.model);
    const State<VP> s = runFor<VP>(sc, 1.0, d, [](const State<VP>&, Data<VP>&) {});
    impacts = d.stats.impacts;
    return Result{s.theta(0), s.theta(1), s.q(State<VP>::QJ + 1), s.q(State<VP>::QJ + 2)};
  };
  // Apart in the joint angles [rad] and in the eccentricity [m].
  auto angles = [](const Result& a, const Result& b) {
    return std::max(std::fabs(a.theta1 - b.theta1), std::fabs(a.theta2 - b.theta2));
  };
  auto ecc = [](const Result& a, const Result& b) { return std::hypot(a.ecc_x - b.ecc_x, a.ecc_y - b.ecc_y); };
  for (const char* law : {"ambrosio", "coulomb"}) {
    const Scene planar = test::scene("planar_clearance", {std::string("friction.law=") + law, "sim.substep=1e-5"});
    const Scene spatial = withKinds(planar, CK::Ideal, CK::Spatial);
    long long impacts = 0, impacts_fine = 0;
    const Result rp = planarRun(planar, impacts);
    Data<VS> ds(spatial.model);
    double max_tilt = 0.0;
    const State<VS> ss = runFor<VS>(spatial, 1.0, ds, [&](const State<VS>& s, Data<VS>&) {
      const auto g = group2(s);
      max_tilt = std::max({max_tilt, std::fabs(g(2)), std::fabs(g(3))});
    });
    const auto g = group2(ss);
    const Result rs{ss.theta(0), ss.theta(1), g(0), g(1)};
    Scene nudged = spatial;
    nudged.run.initial.ecc[1].x() += 1e-15;  // [m]
    Data<VS> dn(nudged.model);
    const State<VS> sn = runFor<VS>(nudged, 1.0, dn, [](const State<VS>&, Data<VS>&) {});
    const auto gn = group2(sn);
    const Result rn{sn.theta(0), sn.theta(1), gn(0), gn(1)};
    EXPECT_EQ(max_tilt, 0.0) << law << ": the symmetric pair of end forces cannot tilt the journal";
    ASSERT_GT(impacts, 5) << law;
    // Each planar impact is one onset at each of the two ends, at once.
    EXPECT_EQ(ds.stats.impacts, 2 * impacts) << law;
    EXPECT_EQ(ds.stats.impacts_joint[1], ds.stats.impacts) << law;
    const Result rf = planarRun(test::scene("planar_clearance", {std::string("friction.law=") + law,
                                                                  "sim.substep=5e-6"}), impacts_fine);
    std::printf("%s: spatial - planar %.3g rad, %.3g m; planar h - h/2 %.3g rad, %.3g m; "
                "spatial round-off spread %.3g rad, %.3g m; impacts %lld\n",
                law, angles(rs, rp), ecc(rs, rp), angles(rf, rp), ecc(rf, rp), angles(rn, rs), ecc(rn, rs), impacts);
    if (std::string(law) == "ambrosio") {
      EXPECT_LT(angles(rs, rp), 1e-9) << law;
      EXPECT_LT(ecc(rs, rp), 1e-10) << law;
    } else {
      EXPECT_LT(angles(rs, rp), angles(rf, rp) + angles(rn, rs))
          << law << ": further apart than the integrator's own error and round-off";
      EXPECT_LT(ecc(rs, rp), ecc(rf, rp) + ecc(rn, rs))
          << law << ": further apart than the integrator's own error and round-off";
    }
  }
}

/// Largest relative drift of the linear and angular momentum over a run.
template <class V>
void expectMomentumHeld(const Scene& sc, double T, const char* what) {
  Data<V> d(sc.model);
  const Momentum h0 = test::momentumOf(sc.model, initialState<V>(sc.run.initial));
  double lin = 0.0, ang = 0.0, lin_scale = 0.0, ang_scale = h0.scale;
  runFor<V>(sc, T, d, [&](const State<V>& s, Data<V>&) {
    const Momentum h = test::momentumOf(sc.model, s);
    lin = std::max(lin, (h.linear - h0.linear).norm());
    ang = std::max(ang, (h.angular - h0.angular).norm());
    lin_scale = std::max(lin_scale, h.scale_linear);
    ang_scale = std::max(ang_scale, h.scale);
  });
  std::printf("%s: impacts joint 1 %lld, joint 2 %lld; momentum drift linear %.3g, angular %.3g (relative)\n", what,
              d.stats.impacts_joint[0], d.stats.impacts_joint[1], lin / lin_scale, ang / ang_scale);
  for (int j = 0; j < 2; ++j) {
    if (V::kind(j) != CK::Ideal) EXPECT_GT(d.stats.impacts_joint[j], 0) << what << ": joint " << j + 1;
  }
  EXPECT_LT(lin / lin_scale, 1e-10) << what;
  EXPECT_LT(ang / ang_scale, 1e-10) << what;
}

// Check 2: the contact pair is internal, so momentum is held through impacts
// at every end of every clearance joint.
TEST(SpatialStepping, MomentumHeldThroughImpactsAtEveryEnd) {
  const Scene sc = test::scene("paper_clearance", {"sim.substep=1e-5", "initial.dtheta1=0.3",
                                                   "initial.ecc2=[1.0e-4, -2.0e-4]"});
  expectMomentumHeld<Shape<CK::Ideal, CK::Spatial>>(withKinds(sc, CK::Ideal, CK::Spatial), 0.3, "spatial 2");
  expectMomentumHeld<Shape<CK::Planar, CK::Planar>>(withKinds(sc, CK::Planar, CK::Planar), 0.3, "planar 1+2");
  expectMomentumHeld<Shape<CK::Spatial, CK::Spatial>>(withKinds(sc, CK::Spatial, CK::Spatial), 0.3,
                                                       "spatial 1+2");
  expectMomentumHeld<Shape<CK::Planar, CK::Ideal>>(withKinds(sc, CK::Planar, CK::Ideal), 0.3, "planar 1");
}

/// Kinetic energy plus the Hertz springs' energy, relative to the kinetic
/// energy scale: its largest change over a run without torque.
template <class V>
double energyChange(const Scene& sc, double T, long long& impacts) {
  Data<V> d(sc.model);
  auto total = [&](const State<V>& s) {
    return test::momentumOf(sc.model, s).energy + hertzEnergy<V>(sc.model, s.q, s.v);
  };
  const double E0 = total(initialState<V>(sc.run.initial));
  double worst = 0.0;
  runFor<V>(sc, T, d, [&](const State<V>& s, Data<V>&) { worst = std::max(worst, std::fabs(total(s) - E0)); });
  impacts = d.stats.impacts;
  return worst / E0;
}

// Check 3: without damping and friction energy is held: exactly (to the
// integrator) for the planar kinds, to about 1e-5 of the kinetic energy for
// the spatial kind (its journal point is first order in the tilt).
TEST(SpatialStepping, EnergyHeldWithoutDampingOrFriction) {
  Scene sc = test::scene("paper_clearance", {"contact.damping=none", "friction.law=none", "sim.substep=1e-5",
                                             "initial.dtheta1=0.5", "initial.dtheta2=-0.8",
                                             "initial.ecc2=[1.0e-4, -2.0e-4]"});
  sc.run.torque.setZero();
  long long n = 0;
  const double planar = energyChange<Shape<CK::Planar, CK::Planar>>(withKinds(sc, CK::Planar, CK::Planar), 0.3, n);
  std::printf("planar 1+2: energy change %.3g of E0, impacts %lld\n", planar, n);
  EXPECT_GT(n, 3);
  EXPECT_LT(planar, 1e-8);
  const double spatial =
      energyChange<Shape<CK::Spatial, CK::Spatial>>(withKinds(sc, CK::Spatial, CK::Spatial), 0.3, n);
  std::printf("spatial 1+2: energy change %.3g of E0, impacts %lld\n", spatial, n);
  EXPECT_GT(n, 3);
  EXPECT_LT(spatial, 1e-5);
}

/// Boresight at T of a scene of shape V with the sub-step h.
template <class V>
Vec3 boresightAt(const std::string& scene, double T, double h) {
  const Scene sc = test::scene(scene, {"sim.substep=" + std::to_string(h)});
  return test::boresightOf(sc.model, test::runTo<V>(sc, T));
}

// Each shipped scene's boresight at 5 s settles as the sub-step shrinks (but
// paper_both_spatial, which is chaotic: check 5 below takes its statistics): the
// two fine settings (1e-5 s, 5e-6 s) agree to 5e-5 rad (measured 9.3e-6,
// 1.4e-5, 3.6e-6; from the scenes' 2e-5 s to 1e-5 s 2.2e-5, 3.4e-5, 4.9e-6).
TEST(SpatialStepping, ShippedScenesConvergeAsTheSubstepShrinks) {
  using CK = ClearanceKind;
  const double T = 5.0;
  auto check = [&](const char* scene, Vec3 (*at)(const std::string&, double, double)) {
    const double fine = test::angleBetween(at(scene, T, 1e-5), at(scene, T, 5e-6));
    std::printf("%s: boresight at 5 s, sub-step 1e-5 vs 5e-6: %.3g rad\n", scene, fine);
    EXPECT_LT(fine, 5e-5) << scene;
  };
  check("paper_spatial2", &boresightAt<Variant<true, CK::Ideal, CK::Spatial, true>>);
  check("paper_both_planar", &boresightAt<Variant<true, CK::Planar, CK::Planar, true>>);
  check("planar_spatial2", &boresightAt<Variant<true, CK::Ideal, CK::Spatial, true>>);
}

/// What a chaotic run keeps whatever its trajectory: over the window
/// [t0, T], per joint, the impacts, the mean tilt gamma and the mean
/// mid-plane eccentricity |p|; and the boresight at t0 and at T.
struct ChaosStats {
  std::array<long long, 2> impacts{};
  std::array<double, 2> mean_tilt_rad{}, mean_ecc_m{}, contact_fraction{};
  Vec3 bore_t0, bore_T;
};

template <class V>
ChaosStats chaosStats(const Scene& sc, double t0, double T) {
  static_assert(V::kind(0) == CK::Spatial && V::kind(1) == CK::Spatial, "both joints spatial");
  Data<V> d(sc.model);
  ChaosStats out;
  std::array<long long, 2> impacts_t0{};
  long long samples = 0;
  const State<V> s = runFor<V>(sc, T, d, [&](const State<V>& s, Data<V>& dd) {
    if (std::fabs(s.t - t0) < 0.5 * sc.model.integrator.step) {
      impacts_t0 = dd.stats.impacts_joint;
      out.bore_t0 = test::boresightOf(sc.model, s);
    }
    if (s.t < t0) return;
    ++samples;
    for (int j = 0; j < 2; ++j) {
      const auto g = s.q.template segment<5>(State<V>::QJ + V::group(j));  // p_x, p_y, alpha, beta, theta
      out.mean_tilt_rad[j] += std::acos(std::cos(g(2)) * std::cos(g(3)));
      out.mean_ecc_m[j] += std::hypot(g(0), g(1));
      const int e = V::firstEnd(j);
      out.contact_fraction[j] += (s.in_contact[e] || s.in_contact[e + 1]) ? 1.0 : 0.0;
    }
  });
  for (int j = 0; j < 2; ++j) {
    out.impacts[j] = d.stats.impacts_joint[j] - impacts_t0[j];
    out.mean_tilt_rad[j] /= static_cast<double>(samples);
    out.mean_ecc_m[j] /= static_cast<double>(samples);
    out.contact_fraction[j] /= static_cast<double>(samples);
  }
  out.bore_T = test::boresightOf(sc.model, s);
  return out;
}

// Check 5: with both joints spatial the paper's manoeuvre is chaotic. Runs
// whose journal 2 starts 1e-12 m off centre agree over the first fraction of
// a second and then part; afterwards they are compared by their statistics.
// The impact counts are not one of them: the journals switch between
// sustained contact and bouncing (45 to 405 onsets of joint 1 over 0.5-5 s
// in four such runs). The tilt is: both journals ride near the bearing's
// limit 2c/L, each run's mean tilt over 0.5-3 s within 5 % of the three
// runs' mean (within 6 % over 0.5-5 s), so 15 % is asked.
TEST(SpatialStepping, BothSpatialIsChaoticButItsStatisticsSettle) {
  using V = Shape<CK::Spatial, CK::Spatial>;
  const double t0 = 0.5, T = 3.0;
  std::vector<ChaosStats> runs;
  for (const char* ecc : {"[0, 0]", "[1e-12, 0]", "[0, 1e-12]"}) {
    runs.push_back(chaosStats<V>(test::scene("paper_both_spatial", {std::string("initial.ecc2=") + ecc}), t0, T));
  }
  const Scene sc = test::scene("paper_both_spatial");
  const double limit = std::atan(2.0 * sc.model.bearing[1].clearance / sc.model.bearing[1].bearing_length);
  for (std::size_t k = 1; k < runs.size(); ++k) {
    const double early = test::angleBetween(runs[0].bore_t0, runs[k].bore_t0);
    const double late = test::angleBetween(runs[0].bore_T, runs[k].bore_T);
    std::printf("run %zu: boresight against run 0: %.3g rad at %.1f s, %.3g rad at %.1f s\n", k, early, t0, late, T);
    EXPECT_LT(early, 1e-5) << k;        // over the first half second a trajectory comparison holds
    EXPECT_GT(late, 100.0 * early) << k;  // then the runs part
  }
  for (int j = 0; j < 2; ++j) {
    double mean = 0.0;
    for (const ChaosStats& r : runs) mean += r.mean_tilt_rad[j] / static_cast<double>(runs.size());
    for (std::size_t k = 0; k < runs.size(); ++k) {
      const ChaosStats& r = runs[k];
      std::printf("run %zu joint %d: impacts %lld, mean tilt %.4g rad (limit %.4g), mean |p| %.3g m, in contact %.3g\n",
                  k, j + 1, r.impacts[j], r.mean_tilt_rad[j], limit, r.mean_ecc_m[j], r.contact_fraction[j]);
      EXPECT_GT(r.impacts[j], 0) << k << " joint " << j + 1;
      EXPECT_NEAR(r.mean_tilt_rad[j], mean, 0.15 * mean) << k << " joint " << j + 1;
      EXPECT_LT(r.mean_tilt_rad[j], limit) << k << " joint " << j + 1;
      EXPECT_GT(r.mean_tilt_rad[j], 0.5 * limit) << k << " joint " << j + 1;
    }
  }
}

}  // namespace
}  // namespace gimbalsim
