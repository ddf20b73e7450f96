// gimbalsim_workprec: the pieces, and a --quick run of the program whose CSV
// must have its columns and show RK4's fourth order on the ideal scene.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <vector>

#include "../csv_util.hpp"
#include "points.hpp"
#include "policies.hpp"
#include "workprec.hpp"

namespace gimbalsim::workprec {
namespace {

TEST(Workprec, ExpandsTheStepInPolicySettings) {
  EXPECT_EQ(expandSet("sim.event_tol=1e-9", 1e-3), "sim.event_tol=1e-9");
  const std::string s = expandSet("sim.substep={h}*0.02", 1e-3);
  ASSERT_EQ(s.rfind("sim.substep=", 0), 0u) << s;
  EXPECT_DOUBLE_EQ(std::stod(s.substr(12)), 2e-5) << s;
  EXPECT_DOUBLE_EQ(std::stod(expandSet("sim.substep={h}", 5e-3).substr(12)), 5e-3);
}

TEST(Workprec, ReadsThePolicyTableAndRefusesAMalformedOne) {
  const auto pols = loadPolicies(std::string(GIMBALSIM_WORKPREC_DIR) + "/policies.yaml");
  ASSERT_GE(pols.size(), 3u);
  EXPECT_EQ(pols.front().name, "plain");
  EXPECT_FALSE(pols.front().contact_only) << "the plain curve must run on the ideal scene too";
  const std::string bad = std::string(GIMBALSIM_TEST_TMP) + "/bad_policies.yaml";
  std::ofstream(bad) << "policies:\n  - name: x\n    sets: [\"sim.substep=1e-5\"]\n  - name: y\n    sest: []\n";
  try {
    loadPolicies(bad);
    FAIL() << "a misspelt field was accepted";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("bad_policies.yaml:4"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'sest'"), std::string::npos) << msg;
  }
}

TEST(Workprec, ErrorsAreTheBoresightAngleAndJointAnglesAtEveryRow) {
  Trajectory ref, run;
  for (int i = 0; i < 3; ++i) {
    ref.t.push_back(0.1 * i), run.t.push_back(0.1 * i);
    ref.theta1.push_back(0.0), run.theta1.push_back(i == 1 ? 2e-4 : 0.0);
    ref.theta2.push_back(0.0), run.theta2.push_back(0.0);
    ref.bore.push_back(Vec3::UnitX());
    const double a = i == 1 ? 3e-3 : 1e-6;  // rotated about z by a
    run.bore.emplace_back(std::cos(a), std::sin(a), 0.0);
  }
  ref.peak_contact = 100.0;
  run.peak_contact = 103.0;
  Point p;
  ASSERT_TRUE(compare(run, ref, p)) << p.note;
  EXPECT_NEAR(p.bore_err_max, 3e-3, 1e-12);
  EXPECT_NEAR(p.bore_err_end, 1e-6, 1e-12);
  EXPECT_NEAR(p.theta1_err_max, 2e-4, 1e-15);
  EXPECT_NEAR(p.peak_force_err_rel, 0.03, 1e-12);
  run.t.pop_back();
  EXPECT_FALSE(compare(run, ref, p)) << "rows that do not line up are not compared";
}

TEST(Workprec, ParetoAndCheapestSettingForATarget) {
  auto pt = [](const char* scene, double cpu, double err, bool ok = true) {
    Point p;
    p.scene = scene, p.cpu_per_sim_s = cpu, p.bore_err_max = err, p.ok = ok;
    return p;
  };
  std::vector<Point> pts = {pt("a", 1.0, 1e-3), pt("a", 2.0, 1e-6), pt("a", 3.0, 1e-4),
                            pt("a", 0.5, 1e-12, false), pt("b", 5.0, 1e-2)};
  markPareto(pts);
  EXPECT_TRUE(pts[0].pareto);
  EXPECT_TRUE(pts[1].pareto);
  EXPECT_FALSE(pts[2].pareto) << "dearer and less accurate than point 1";
  EXPECT_FALSE(pts[3].pareto) << "a failed run is never on the front";
  EXPECT_TRUE(pts[4].pareto) << "fronts are per scene";
  EXPECT_EQ(cheapestFor(pts, "a", 1e-3), &pts[0]);
  EXPECT_EQ(cheapestFor(pts, "a", 1e-5), &pts[1]);
  EXPECT_EQ(cheapestFor(pts, "a", 1e-9), nullptr) << "the failed run's error does not count";
}

TEST(Workprec, QuickRunWritesTheCsvAndErrorsFallAtFourthOrderOnTheIdealScene) {
  const std::string dir = std::string(GIMBALSIM_TEST_TMP) + "/quick";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string cmd = std::string(GIMBALSIM_WORKPREC_BIN) +
                          " --scenes-dir " GIMBALSIM_SCENES_DIR " --policies " GIMBALSIM_WORKPREC_DIR "/policies.yaml"
                          " --quick --scenes paper_ideal,stickslip_clearance --policy plain --policy 'sub h/50'"
                          " --out " + dir + " > " + dir + ".log 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << "see " << dir << ".log";
  const test::Csv csv = test::Csv::read(dir + "/workprec.csv");
  EXPECT_EQ(csv.header, kCsvColumns);
  {  // text cells unquoted: numpy's readers take a quote for part of the text
    std::ifstream in(dir + "/workprec.csv");
    const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    EXPECT_EQ(text.find('"'), std::string::npos) << text.substr(0, 400);
  }
  std::vector<std::pair<double, double>> ideal;  // (h, bore_err_max)
  bool clearance_point = false;
  for (const auto& r : csv.records()) {
    if (r.at("scene") == "paper_ideal" && r.at("policy") == "plain") {
      ASSERT_EQ(r.at("ok"), "1") << r.at("note");
      EXPECT_GT(std::stod(r.at("cpu_s_per_sim_s")), 0.0);
      ideal.emplace_back(std::stod(r.at("h_s")), std::stod(r.at("bore_err_max_rad")));
      // no contact, no force error: nan with its reason beside it (the CSV convention)
      EXPECT_EQ(r.at("peak_force_err_rel"), "nan");
      EXPECT_EQ(r.at("note"), "peak_force_err_rel: no contact in the reference");
    }
    if (r.at("scene") == "stickslip_clearance" && r.at("ok") == "1") {
      clearance_point = true;
      EXPECT_GT(std::stoll(r.at("substeps")), 0);
    }
  }
  ASSERT_EQ(ideal.size(), 3u);
  std::sort(ideal.rbegin(), ideal.rend());  // h decreasing
  for (std::size_t i = 0; i + 1 < ideal.size(); ++i) {
    const double ratio = ideal[i].second / ideal[i + 1].second;
    // Halving h divides RK4's error by about 16; demand at least 8.
    EXPECT_GT(ratio, 8.0) << "h " << ideal[i].first << " -> " << ideal[i + 1].first << ": error "
                          << ideal[i].second << " -> " << ideal[i + 1].second;
  }
  EXPECT_TRUE(clearance_point) << "no point of the stick-slip scene ran";
}

TEST(Workprec, CoversClearanceInBothJointsAndASpatialJoint) {
  // The new joint kinds against their reference (Ambrosio friction, the
  // tool's default for them): each point ran, sub-stepped, and the error
  // falls as the sub-step shrinks with h (measured: 5.3e-6 to 2.5e-8 rad,
  // both planar). (At h = 40 ms a spatial journal's tilt diverges in free
  // flight and the run stops naming sim.velocity_limit: not swept here.)
  const std::string dir = std::string(GIMBALSIM_TEST_TMP) + "/kinds";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string cmd = std::string(GIMBALSIM_WORKPREC_BIN) +
                          " --scenes-dir " GIMBALSIM_SCENES_DIR " --policies " GIMBALSIM_WORKPREC_DIR "/policies.yaml"
                          " --duration 0.4 --output-interval 0.04 --peak-dt 1e-5 --steps 4e-3,2e-3,1e-3 --repeats 1"
                          " --no-mujoco --scenes paper_both_planar,paper_spatial2 --policy 'sub h/50'"
                          " --out " + dir + " > " + dir + ".log 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << "see " << dir << ".log";
  std::map<std::string, std::vector<std::pair<double, double>>> err;  // scene -> (h, bore_err_max)
  for (const auto& r : test::Csv::read(dir + "/workprec.csv").records()) {
    ASSERT_EQ(r.at("ok"), "1") << r.at("scene") << ": " << r.at("note");
    EXPECT_GT(std::stoll(r.at("substeps")), 0) << r.at("scene");
    err[r.at("scene")].emplace_back(std::stod(r.at("h_s")), std::stod(r.at("bore_err_max_rad")));
  }
  ASSERT_EQ(err.size(), 2u);
  for (auto& [scene, pts] : err) {
    ASSERT_EQ(pts.size(), 3u) << scene;
    std::sort(pts.rbegin(), pts.rend());  // h decreasing
    EXPECT_LT(pts.back().second, pts.front().second) << scene << ": finer settings must be closer to the reference";
    EXPECT_LT(pts.back().second, 1e-6) << scene;
  }
}

}  // namespace
}  // namespace gimbalsim::workprec
