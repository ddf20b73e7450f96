// The run summary (io::runSummary) holds only true fields for every
// integrator: each is checked against what the rows themselves show (the
// largest contact force, penetration and joint-2 force of any row, the number
// of contact onsets seen between rows, the last row's time and state); the
// RK4's step counters are absent for the reference, which has none.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "gimbalsim/dynamics/simulate.hpp"
#include "gimbalsim/run_output/run_output.hpp"
#include "test_util.hpp"

namespace gimbalsim {
namespace {

struct Case {
  IntegratorKind kind;
  const char* name;
};

class Summary : public ::testing::TestWithParam<Case> {};

TEST_P(Summary, EveryFieldAgreesWithTheRows) {
  // A row every step, so a contact of the rows is one of the run; coulomb_stick,
  // which the reference can integrate (plain Coulomb's jump stops it).
  const Scene sc =
      test::scene("paper_clearance", {"sim.duration=0.3", "sim.output_interval=1e-3", "friction.law=coulomb_stick"});
  std::vector<Row> rows;
  const RunResult r = simulate(sc, [&](const Row& row) { rows.push_back(row); }, GetParam().kind);
  ASSERT_TRUE(r.ok) << r.error;
  const nlohmann::json j = io::runSummary(sc.model, r, "paper_clearance.yaml", GetParam().name);

  double max_fn = 0.0, max_delta = 0.0, max_j2 = 0.0;
  long long onsets = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    max_fn = std::max(max_fn, rows[i].fn2);
    max_delta = std::max(max_delta, rows[i].delta2);
    max_j2 = std::max(max_j2, rows[i].joint2_force);
    if (i > 0 && rows[i].delta2 > 0.0 && !(rows[i - 1].delta2 > 0.0)) ++onsets;
  }
  ASSERT_GT(onsets, 0) << "the scene must hit the bearing in 0.3 s";
  ASSERT_GT(max_fn, 0.0);

  EXPECT_EQ(j["rows"].get<long long>(), static_cast<long long>(rows.size()));
  EXPECT_EQ(j["t_end_s"].get<double>(), rows.back().t);
  EXPECT_EQ(j["status"], "ok");
  // Peaks are tracked between rows too: at least the rows' largest, never a null time.
  EXPECT_GE(j["peak_contact_force_N"].get<double>(), max_fn);
  ASSERT_TRUE(j["t_peak_contact_force_s"].is_number());
  EXPECT_GE(j["t_peak_contact_force_s"].get<double>(), 0.0);
  EXPECT_LE(j["t_peak_contact_force_s"].get<double>(), rows.back().t);
  EXPECT_GE(j["max_penetration_m"].get<double>(), max_delta);
  EXPECT_GE(j["peak_joint2_force_N"].get<double>(), max_j2);
  // Every onset the rows show is a located impact; each impact but one still open has its separation.
  EXPECT_GE(j["impacts"].get<long long>(), onsets);
  EXPECT_GE(j["separations"].get<long long>(), j["impacts"].get<long long>() - 1);
  EXPECT_LE(j["separations"].get<long long>(), j["impacts"].get<long long>());
  EXPECT_EQ(j["final_state"]["q"]["theta1"].get<double>(), rows.back().theta1);
  EXPECT_EQ(j["final_state"]["q"]["theta2"].get<double>(), rows.back().theta2);
  EXPECT_EQ(j["final_state"]["v"]["dtheta1"].get<double>(), rows.back().dtheta1);

  const bool rk4 = GetParam().kind == IntegratorKind::Rk4;
  for (const char* k : {"steps", "substeps", "event_iterations", "max_substeps_in_a_step", "straddle_retries",
                        "adaptive_rejected_substeps", "adaptive_forced_substeps", "min_impact_duration_s"}) {
    EXPECT_EQ(j.contains(k), rk4) << k;
  }
  EXPECT_EQ(j["integrator"].contains("substep_s"), rk4);
  if (rk4) {
    // One RK4 step per sim.step, and at least one sub-step each.
    EXPECT_EQ(j["steps"].get<long long>(), static_cast<long long>(rows.size()) - 1);
    EXPECT_GE(j["substeps"].get<long long>(), j["steps"].get<long long>());
  }
}

INSTANTIATE_TEST_SUITE_P(Integrators, Summary,
                         ::testing::Values(Case{IntegratorKind::Rk4, "rk4"}, Case{IntegratorKind::Reference, "reference"}),
                         [](const auto& info) { return std::string(info.param.name); });

// Both integrators find the same impacts and peak force (measured: 846.78 N
// and 846.86 N, 1e-4 apart; the reference's used to be 0).
TEST(Summary, ClearanceJointsCountTheirOwnImpactsAndTilt) {
  // Both joints with clearance: each joint's impacts add up to the run's; the
  // elevation journal's tilt is bounded by its bearing (2 c / L, plus the
  // penetration's share); a planar joint reports no tilt.
  // (the momentum guard off: a free azimuth journal's first steps drift by more
  // than 1e-9 of the still tiny momenta; this test is about the joints' fields)
  const Scene sc =
      test::scene("paper_spatial2", {"sim.duration=0.5", "structure.joint1=planar", "sim.momentum_tol=0"});
  const RunResult r = simulate(sc, [](const Row&) {});
  ASSERT_TRUE(r.ok) << r.error;
  const nlohmann::json j = io::runSummary(sc.model, r, "paper_spatial2.yaml", "rk4");
  const nlohmann::json& c = j["clearance_joints"];
  ASSERT_TRUE(c.contains("joint1") && c.contains("joint2")) << c.dump();
  EXPECT_EQ(c["joint1"]["kind"], "planar");
  EXPECT_EQ(c["joint2"]["kind"], "spatial");
  EXPECT_FALSE(c["joint1"].contains("max_tilt_rad"));
  const long long i1 = c["joint1"]["impacts"].get<long long>(), i2 = c["joint2"]["impacts"].get<long long>();
  EXPECT_GT(i2, 0);
  EXPECT_EQ(i1 + i2, j["impacts"].get<long long>());
  const double tilt = c["joint2"]["max_tilt_rad"].get<double>();
  const ContactParams& cp = sc.model.bearing[1];
  EXPECT_GT(tilt, 0.1 * 2.0 * cp.clearance / cp.bearing_length) << "the paper's manoeuvre tilts the journal";
  EXPECT_LT(tilt, 1.2 * 2.0 * cp.clearance / cp.bearing_length);
  EXPECT_LE(c["joint2"]["peak_contact_force_N"].get<double>(), j["peak_contact_force_N"].get<double>());
  const nlohmann::json ideal =
      io::runSummary(test::scene("paper_ideal").model, simulate(test::scene("paper_ideal", {"sim.duration=0.01"}),
                                                                [](const Row&) {}),
                     "paper_ideal.yaml", "rk4");
  EXPECT_FALSE(ideal.contains("clearance_joints"));
}

TEST(Summary, EachBearingEndAgreesWithTheRowsAndTheGeometry) {
  // Both joints spatial, a row every step: the per-end columns and the
  // summary's ends hold together, and each row obeys the bearing's geometry.
  // The two end points of the journal axis lie L tan(gamma) apart in the end
  // planes' projection and the mid-plane centre p is their midpoint, so
  // |delta_plus - delta_minus| <= L tan(gamma) and |p| <= c + mean delta.
  const Scene sc = test::scene("paper_both_spatial", {"sim.duration=0.4", "sim.output_interval=2.5e-4"});
  std::vector<Row> rows;
  const RunResult r = simulate(sc, [&](const Row& row) { rows.push_back(row); });
  ASSERT_TRUE(r.ok) << r.error;
  const nlohmann::json j = io::runSummary(sc.model, r, "paper_both_spatial.yaml", "rk4");
  struct JointCols {
    double Row::*ecc, Row::*delta, Row::*fn, Row::*tilt, Row::*d_minus, Row::*d_plus, Row::*f_minus, Row::*f_plus;
    const char* name;
    const ContactParams& cp;
  };
  const JointCols joints[2] = {
      {&Row::ecc1, &Row::delta1, &Row::fn1, &Row::tilt1, &Row::delta1_minus, &Row::delta1_plus, &Row::fn1_minus,
       &Row::fn1_plus, "joint1", sc.model.bearing[0]},
      {&Row::ecc2, &Row::delta2, &Row::fn2, &Row::tilt2, &Row::delta2_minus, &Row::delta2_plus, &Row::fn2_minus,
       &Row::fn2_plus, "joint2", sc.model.bearing[1]}};
  long long all_ends = 0;
  for (const JointCols& jc : joints) {
    SCOPED_TRACE(jc.name);
    const nlohmann::json& o = j["clearance_joints"][jc.name];
    ASSERT_TRUE(o.contains("ends")) << o.dump();
    const long long n_minus = o["ends"]["minus"]["impacts"].get<long long>();
    const long long n_plus = o["ends"]["plus"]["impacts"].get<long long>();
    EXPECT_EQ(n_minus + n_plus, o["impacts"].get<long long>());
    all_ends += n_minus + n_plus;
    const double L = jc.cp.bearing_length, c = jc.cp.clearance;
    double peak_minus = 0.0, peak_plus = 0.0, max_tilt = 0.0;
    long long onsets_minus = 0, onsets_plus = 0, asymmetric = 0;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const Row& w = rows[i];
      const double dm = w.*jc.d_minus, dp = w.*jc.d_plus, tilt = w.*jc.tilt;
      ASSERT_LE(std::abs(dp - dm), L * std::tan(tilt) * (1.0 + 1e-9) + 1e-15) << "t = " << w.t;
      ASSERT_LE(w.*jc.ecc, c + 0.5 * (dm + dp) + 1e-15) << "t = " << w.t;
      EXPECT_EQ(w.*jc.delta, std::max(dm, dp));
      // Hertz: a force only where the end penetrates.
      if (!(dm > 0.0)) EXPECT_EQ(w.*jc.f_minus, 0.0) << "t = " << w.t;
      if (!(dp > 0.0)) EXPECT_EQ(w.*jc.f_plus, 0.0) << "t = " << w.t;
      EXPECT_NEAR(w.*jc.fn, w.*jc.f_minus + w.*jc.f_plus, 1e-12 * (1.0 + w.*jc.fn));
      if (dm > 0.0 && !(dp > 0.0)) ++asymmetric;
      peak_minus = std::max(peak_minus, w.*jc.f_minus), peak_plus = std::max(peak_plus, w.*jc.f_plus);
      max_tilt = std::max(max_tilt, tilt);
      if (i > 0 && dm > 0.0 && !((rows[i - 1].*jc.d_minus) > 0.0)) ++onsets_minus;
      if (i > 0 && dp > 0.0 && !((rows[i - 1].*jc.d_plus) > 0.0)) ++onsets_plus;
    }
    EXPECT_GT(asymmetric, 0) << "a tilted journal touches at one end alone";
    EXPECT_GE(n_minus, onsets_minus);
    EXPECT_GE(n_plus, onsets_plus);
    EXPECT_GT(onsets_minus + onsets_plus, 0);
    EXPECT_GE(o["ends"]["minus"]["peak_contact_force_N"].get<double>(), peak_minus);
    EXPECT_GE(o["ends"]["plus"]["peak_contact_force_N"].get<double>(), peak_plus);
    EXPECT_EQ(o["peak_contact_force_N"].get<double>(), std::max(o["ends"]["minus"]["peak_contact_force_N"].get<double>(),
                                                                 o["ends"]["plus"]["peak_contact_force_N"].get<double>()));
    EXPECT_GE(o["max_tilt_rad"].get<double>(), max_tilt);
    EXPECT_GT(max_tilt, 0.0);
  }
  EXPECT_EQ(all_ends, j["impacts"].get<long long>());
  // The run's peak is one end's force, the largest of the four ends' peaks.
  double ends_peak = 0.0;
  for (const char* jn : {"joint1", "joint2"}) {
    for (const char* side : {"minus", "plus"}) {
      ends_peak = std::max(ends_peak, j["clearance_joints"][jn]["ends"][side]["peak_contact_force_N"].get<double>());
    }
  }
  EXPECT_EQ(j["peak_contact_force_N"].get<double>(), ends_peak);
}

TEST(Summary, ThePeakForceOfBothIntegratorsAgrees) {
  const Scene sc = test::scene("paper_clearance", {"sim.duration=0.3", "friction.law=coulomb_stick"});
  const RunResult a = simulate(sc, [](const Row&) {}, IntegratorKind::Rk4);
  const RunResult b = simulate(sc, [](const Row&) {}, IntegratorKind::Reference);
  ASSERT_TRUE(a.ok && b.ok) << a.error << b.error;
  EXPECT_NEAR(b.stats.peak_fn, a.stats.peak_fn, 1e-3 * a.stats.peak_fn);
  EXPECT_EQ(b.stats.impacts, a.stats.impacts);
}

TEST(Summary, NoDriftOverNoStepAndNoRelativeDriftOverNoScale) {
  // (pass 82) a run stopped in its first step gave angular_relative 0.0 over a scale of 0
  const Scene stopped = test::scene("paper_clearance", {"sim.duration=0.01", "sim.velocity_limit=1e-300"});
  const RunResult r = simulate(stopped, [](const Row&) {}, IntegratorKind::Rk4);
  ASSERT_FALSE(r.ok);
  const nlohmann::json d = io::runSummary(stopped.model, r, "s.yaml", "rk4")["momentum_drift"];
  for (const char* k : {"linear_max_abs_Ns", "angular_max_abs_Nms", "angular_scale_Nms", "angular_relative"}) {
    EXPECT_TRUE(d[k].is_null()) << k << ": " << d.dump();
  }
  EXPECT_EQ(d["reason"], "the run stopped in its first step: no drift over no step") << d.dump();
  // nothing turns: no torque, no initial rate
  const Scene still = test::scene("paper_ideal", {"sim.duration=0.01", "torque.tau1=0", "torque.tau2=0"});
  const RunResult s = simulate(still, [](const Row&) {}, IntegratorKind::Rk4);
  ASSERT_TRUE(s.ok) << s.error;
  const nlohmann::json e = io::runSummary(still.model, s, "s.yaml", "rk4")["momentum_drift"];
  ASSERT_EQ(e["angular_scale_Nms"].get<double>(), 0.0) << e.dump();
  EXPECT_TRUE(e["angular_relative"].is_null()) << e.dump();
  EXPECT_NE(e["reason"].get<std::string>().find("scale is 0 (nothing turned)"), std::string::npos) << e.dump();
  // a run that turned has its relative drift
  const Scene moving = test::scene("paper_ideal", {"sim.duration=0.01"});
  const nlohmann::json m =
      io::runSummary(moving.model, simulate(moving, [](const Row&) {}, IntegratorKind::Rk4), "s.yaml", "rk4");
  EXPECT_LT(m["momentum_drift"]["angular_relative"].get<double>(), 1e-9) << m.dump();
  EXPECT_FALSE(m["momentum_drift"].contains("reason"));
}

}  // namespace
}  // namespace gimbalsim
