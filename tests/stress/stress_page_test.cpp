// The stress tool's pieces that are not the classifier (tools/stress/): the
// grid's definition (its size: the grid before and after a change must make
// the same runs), the page body written to docs/results/stress.md, the CSV.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "stress_csv.hpp"
#include "stress_grid.hpp"
#include "stress_page.hpp"

namespace gimbalsim::stress {
namespace {

TEST(StressGridDefinition, SweepsAndCellsAsBefore) {
  // 86 sweep runs and 3 x 5 x 4 cells (issue 19 split the tool by job; the
  // grid it makes is unchanged but for the three adaptive runs with plain
  // Coulomb friction, which the scene now refuses), then 30 over the joint
  // kinds: 6 scenes x (3 friction laws + strong torques), 2 conservative,
  // 2 x 2 stiffness extremes.
  const std::vector<Case> sw = sweeps("1");
  EXPECT_EQ(sw.size(), 86u + 6 * 4 + 2 + 4);
  EXPECT_EQ(std::count_if(sw.begin(), sw.end(), [](const Case& c) { return c.scene == "paper_both_spatial"; }), 4);
  for (const Case& c : sw) EXPECT_EQ(c.sets.front(), "sim.duration=1");
  const std::vector<Cell> cells = gridCells();
  EXPECT_EQ(cells.size(), 60u);
  Cell adaptive{100.0, 5e-6, Walk::Adaptive, {}, -1};
  const Case c = walkCase(adaptive, 1e-8, "0.5");
  EXPECT_EQ(c.group, "adaptive walk");
  EXPECT_EQ(joined(c.sets), "sim.duration=0.5 contact.stiffness_scale=100 contact.clearance=5e-06 "
                            "sim.substep_policy=adaptive friction.law=ambrosio sim.substep_tol=1e-08");
  EXPECT_EQ(walkedValue(c.sets), "1e-08");
  Cell whole{1.0, 5e-4, Walk::WholeStep, {}, -1};
  EXPECT_EQ(joined(walkCase(whole, 2e-5, "1").sets),
            "sim.duration=1 contact.stiffness_scale=1 contact.clearance=0.0005 sim.substep=2e-05 sim.step=2e-05");
}

Case fabricated(const std::string& group, Verdict v, const char* key = "", const std::string& reason = "") {
  Case c{group, "paper_clearance", {"sim.duration=1", "contact.clearance=5e-06"}, {}, true};
  c.out.verdict = v;
  c.out.run.stop.key = key;
  c.out.reason = reason;
  return c;
}

TEST(StressPage, CountsGroupsStopsAndFailures) {
  std::vector<Case> cases = {fabricated("stiffness", Verdict::Trustworthy),
                             fabricated("stiffness", Verdict::Stopped, "sim.penetration_limit"),
                             fabricated("clearance", Verdict::Stopped, "sim.momentum_tol"),
                             fabricated("clearance", Verdict::SilentlyWrong, "", "energy rise 2e-3")};
  PageInput in;
  for (const Case& c : cases) in.all.push_back(&c);
  in.duration = "1";
  const std::string md = pageBody(in);
  EXPECT_NE(md.find("**4 runs: 1 TRUSTWORTHY, 2 STOPPED with a diagnostic naming the limit, 1 failing**"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("`sim.momentum_tol` 1, `sim.penetration_limit` 1"), std::string::npos) << md;
  EXPECT_NE(md.find("| stiffness | 2 | 1 | 1 | 0 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| clearance | 2 | 0 | 1 | 1 |"), std::string::npos) << md;
  EXPECT_NE(md.find("- SILENTLY_WRONG: `paper_clearance sim.duration=1 contact.clearance=5e-06`: energy rise 2e-3"),
            std::string::npos)
      << md;
  EXPECT_EQ(md.find("README"), std::string::npos);
}

TEST(StressPage, WalkTableShowsTheLargestTrustworthyValueAndEveryVerdict) {
  std::vector<Cell> cells = gridCells();
  for (Cell& cell : cells) {
    if (cell.mode != Walk::Substep || cell.stiffness != 1.0 || cell.clearance != 5e-4) continue;
    for (double h : {1e-3, 5e-4, 2e-4}) {
      Case c = walkCase(cell, h, "1");
      c.out.verdict = h > 3e-4 ? Verdict::Stopped : Verdict::Trustworthy;
      c.out.substeps_per_second = 5000.0;
      cell.walk.push_back(c);
    }
    cell.stable = 2;
  }
  PageInput in;
  in.cells = &cells;
  in.duration = "1";
  const std::string md = pageBody(in);
  EXPECT_NE(md.find("| x1 (8.68e+09) | none  | none  | **0.0002** (5e+03/s) SST | none  |"), std::string::npos) << md;
}

// (pass 55) a study of the long run alone opened with the sweeps' and the walk's description, none of which ran.
TEST(StressPage, TheOpeningNamesOnlyWhatRan) {
  PageInput in;
  in.duration = "1";
  in.csv_path = "d/long.csv";
  in.sweeps_ran = in.grid_ran = false;
  const std::string alone = pageBody(in);
  EXPECT_NE(alone.find("(tools/stress/): the long run alone (no sweep and no sub-step walk ran). The CSV of every "
                       "run is d/long.csv."),
            std::string::npos)
      << alone;
  EXPECT_EQ(alone.find("one parameter changed"), std::string::npos) << alone;
  EXPECT_EQ(alone.find("sim.duration = 1 s"), std::string::npos) << alone;
  in.sweeps_ran = true;
  const std::string sweeps = pageBody(in);
  EXPECT_NE(sweeps.find("with each friction law; sim.duration = 1 s"), std::string::npos) << sweeps;
  EXPECT_EQ(sweeps.find("a walk down the sub-step"), std::string::npos) << sweeps;
  in.grid_ran = true;
  const std::string both = pageBody(in);
  EXPECT_NE(both.find("with each friction law, and for each contact stiffness and clearance a walk down the sub-step "
                      "until the run is trustworthy; sim.duration = 1 s"),
            std::string::npos)
      << both;
}

TEST(StressCsv, OneRowPerRunWithTheVerdict) {
  const Case a = fabricated("torque", Verdict::Stopped, "sim.max_substeps", "cap \"hit\"");
  const std::string csv = csvText({&a});
  EXPECT_EQ(csv.substr(0, csv.find(',')), "group");
  EXPECT_NE(csv.find("\ntorque,paper_clearance,sim.duration=1 contact.clearance=5e-06,STOPPED,cap 'hit',"),
            std::string::npos)
      << csv;
  // '#' starts a comment for numpy's genfromtxt, which reads no quotes: none in any cell, no quote either.
  const Case r = fabricated("torque", Verdict::Refused, "", "--set #1 'sim.duration=0.0025': refused");
  const std::string refused = csvText({&r});
  EXPECT_EQ(refused.find('#'), std::string::npos) << refused;
  EXPECT_EQ(refused.find('"'), std::string::npos) << refused;
  EXPECT_NE(refused.find(",--set no. 1 'sim.duration=0.0025': refused,"), std::string::npos) << refused;
}

TEST(StressCsv, ARefusedRunHasNoFigures) {
  // (pass 45) a refused run's figures were bare 0 (t_end_s 0, impacts 0, wall_s 0): nothing ran, so every
  // column after the reason is nan, and the row has as many cells as the header.
  Case r = fabricated("joint kinds", Verdict::Refused, "", "sc/paper_spatial2.yaml:51:1: unknown key");
  r.out.run.t_end = 0.0;
  const std::string csv = csvText({&r});
  const std::string header = csv.substr(0, csv.find('\n'));
  const std::string row = csv.substr(header.size() + 1, csv.size() - header.size() - 2);
  EXPECT_EQ(std::count(row.begin(), row.end(), ','), std::count(header.begin(), header.end(), ',')) << csv;
  const std::string figures = row.substr(row.find("unknown key,") + 12);
  EXPECT_EQ(figures, "nan,nan,nan,nan,nan,nan,nan,nan,nan,nan,nan,nan,nan") << csv;
}

}  // namespace
}  // namespace gimbalsim::stress
