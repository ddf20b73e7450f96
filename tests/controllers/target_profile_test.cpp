// Target profile: continuity across segments, derivatives against finite
// differences, the documented bounds; losBoresight against the dynamics'
// own kinematics; pointingError exact near 0.
#include <gtest/gtest.h>

#include <cmath>

#include "gimbalsim/input/input_error.hpp"
#include "gimbalsim/pointing/profile_keys.hpp"
#include "gimbalsim/pointing/target_profile.hpp"
#include "gimbalsim/dynamics/simulate.hpp"
#include "test_util.hpp"

namespace gimbalsim::pointing {
namespace {

TargetProfile profile() {
  TargetProfile p;
  p.start = {-0.2, 0.1};
  p.slew_start = 0.5;
  p.slew_target = {0.6, -0.3};
  p.slew_time = 2.0;
  p.hold_time = 1.0;
  p.track_rate = {0.02, -0.01};
  p.track_ramp_time = 0.7;
  p.track_amplitude = {0.01, 0.004};
  p.track_period = {8.0, 5.0};
  return p;
}

TEST(TargetProfile, SegmentsInOrder) {
  const TargetProfile p = profile();
  EXPECT_EQ(p.at(0.0).segment, Segment::Wait);
  EXPECT_EQ(p.at(1.0).segment, Segment::Slew);
  EXPECT_EQ(p.at(3.0).segment, Segment::Hold);
  EXPECT_EQ(p.at(3.6).segment, Segment::Track);
  EXPECT_EQ(p.at(0.0).q, p.start);
  EXPECT_EQ(p.at(3.0).q, p.slew_target);
  EXPECT_EQ(p.at(3.0).dq, Vec2::Zero());
}

TEST(TargetProfile, PositionAndRateContinuousAtEveryBoundary) {
  const TargetProfile p = profile();
  const double eps = 1e-9;
  for (double tb : {p.slew_start, p.slewEnd(), p.trackStart()}) {
    const ProfileSample a = p.at(tb - eps), b = p.at(tb + eps);
    EXPECT_LT((a.q - b.q).norm(), 1e-8) << "position jumps at t = " << tb;
    EXPECT_LT((a.dq - b.dq).norm(), 1e-7) << "rate jumps at t = " << tb;
  }
  // The minimum-jerk slew also starts and ends with zero acceleration.
  for (double tb : {p.slew_start, p.slewEnd()}) {
    EXPECT_LT((p.at(tb - eps).ddq - p.at(tb + eps).ddq).norm(), 1e-6) << "acceleration jumps at t = " << tb;
  }
}

TEST(TargetProfile, DerivativesMatchCentralDifferences) {
  const TargetProfile p = profile();
  const double h = 1e-5;
  int checked = 0;
  for (double t = 0.013; t < 12.0; t += 0.0731) {
    bool near_boundary = false;
    for (double tb : {p.slew_start, p.slewEnd(), p.trackStart()}) near_boundary |= std::fabs(t - tb) < 2 * h;
    if (near_boundary) continue;
    const ProfileSample a = p.at(t - h), b = p.at(t + h), c = p.at(t);
    const Vec2 dq_fd = (b.q - a.q) / (2 * h), ddq_fd = (b.dq - a.dq) / (2 * h);
    EXPECT_LT((dq_fd - c.dq).norm(), 1e-7) << "t = " << t;
    EXPECT_LT((ddq_fd - c.ddq).norm(), 1e-6) << "t = " << t;
    ++checked;
  }
  EXPECT_GT(checked, 150);
}

TEST(TargetProfile, SlewPeakRateIsTheMinimumJerkValue) {
  const TargetProfile p = profile();
  const ProfileSample mid = p.at(p.slew_start + 0.5 * p.slew_time);
  const Vec2 d = p.slew_target - p.start;
  // Minimum jerk: peak rate 15/8 d/T at mid-slew, position half way, zero acceleration.
  EXPECT_NEAR((mid.dq - 1.875 * d / p.slew_time).norm(), 0.0, 1e-12);
  EXPECT_NEAR((mid.q - 0.5 * (p.start + p.slew_target)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(mid.ddq.norm(), 0.0, 1e-12);
}

TEST(TargetProfile, TrackStaysWithinItsDocumentedBounds) {
  const TargetProfile p = profile();
  for (int i = 0; i < 2; ++i) {
    const double w = 2 * M_PI / p.track_period(i);
    const double rate_bound = std::fabs(p.track_rate(i)) + std::fabs(p.track_amplitude(i)) * w;
    const double acc_bound = std::fabs(p.track_rate(i)) / p.track_ramp_time + std::fabs(p.track_amplitude(i)) * w * w;
    double max_rate = 0, max_acc = 0;
    for (double t = p.trackStart(); t < p.trackStart() + 60.0; t += 0.01) {
      max_rate = std::max(max_rate, std::fabs(p.at(t).dq(i)));
      max_acc = std::max(max_acc, std::fabs(p.at(t).ddq(i)));
    }
    EXPECT_LE(max_rate, rate_bound * (1 + 1e-12));
    EXPECT_LE(max_acc, acc_bound * (1 + 1e-12));
    EXPECT_GT(max_rate, 0.5 * rate_bound);  // the bound is not vacuous
  }
  // Long after the ramp the pass moves at the pass rate on average.
  const double t0 = p.trackStart() + 40.0, T = p.track_period(0) * p.track_period(1);  // whole periods of both
  const Vec2 mean_rate = (p.at(t0 + T).q - p.at(t0).q) / T;
  EXPECT_LT((mean_rate - p.track_rate).norm(), 1e-9);
}

// One format for a controller file: the profile: section or flat profile.*
// keys (pointing_controller --print-config) give the same profile; a file
// with neither (a scene) is refused, naming the key.
TEST(TargetProfileFile, SectionAndFlatKeysReadAlike) {
  const TargetProfile nested =
      loadTargetProfileText("profile:\n  slew_start: 0.25\n  slew_time: 1.5\n  hold_time: 0.75\n", "nested.yaml");
  const TargetProfile flat =
      loadTargetProfileText("profile.slew_start: 0.25\nprofile.slew_time: 1.5\nprofile.hold_time: 0.75\n", "flat.yaml");
  EXPECT_EQ(nested.slew_start, 0.25);
  EXPECT_EQ(flat.slew_start, nested.slew_start);
  EXPECT_EQ(flat.slew_time, nested.slew_time);
  EXPECT_EQ(flat.trackStart(), 2.5);
  try {
    loadTargetProfileText("sim:\n  duration: 1\n", "scene.yaml");
    FAIL() << "a file without profile keys was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scene.yaml: key 'profile': missing"), std::string::npos) << e.what();
  }
}

TEST(LosBoresight, MatchesTheDynamicsKinematicsOnAFixedBase) {
  for (const char* scene : {"paper_ideal", "paper_clearance"}) {
    Scene sc = test::scene(scene, {"structure.base=fixed"});
    const Model& m = sc.model;
    for (double az : {-2.0, 0.0, 0.7, 3.0}) {
      for (double el : {-1.2, 0.0, 0.4}) {
        sc.run.initial.theta1 = az;
        sc.run.initial.theta2 = el;
        const Vec3 b = dispatchVariant(m, [&](auto tag) {
          using V = decltype(tag);
          return test::boresightOf<V>(m, initialState<V>(sc.run.initial));
        });
        EXPECT_LT((losBoresight(m, az, el) - b).norm(), 1e-14) << scene << " az " << az << " el " << el;
      }
    }
  }
}

TEST(LosBoresight, PaperGeometryClosedForm) {
  // Azimuth about z, elevation about y, boresight +x: Rz(az) Ry(el) x.
  const Model m = test::model("paper_ideal");
  const double az = 0.9, el = 0.35;
  const Vec3 expected(std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), -std::sin(el));
  EXPECT_LT((losBoresight(m, az, el) - expected).norm(), 1e-15);
}

TEST(PointingError, ExactNearZeroAndAtRightAngles) {
  const Vec3 a = Vec3::UnitX();
  for (double ang : {1e-12, 1e-9, 1e-6, 0.3, M_PI / 2, 3.0}) {
    const Vec3 b(std::cos(ang), std::sin(ang), 0.0);
    EXPECT_NEAR(pointingError(a, b), ang, 1e-15 + 1e-13 * ang) << ang;
    EXPECT_NEAR(pointingError(a, 7.0 * b), ang, 1e-15 + 1e-13 * ang) << "not scale invariant";
  }
  EXPECT_EQ(pointingError(a, a), 0.0);
}

}  // namespace
}  // namespace gimbalsim::pointing
