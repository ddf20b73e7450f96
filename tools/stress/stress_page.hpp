// The stress grid's Markdown: the body of docs/results/stress.md (the header,
// with machine, commit and date, is added by tools/pages/results_page.py, called
// from tools/stress/run_stress.sh). What was run and the verdict counts, the
// three largest-trustworthy-step tables, the effective restitution table and
// the one-hour run.
#pragma once

#include <string>
#include <vector>

#include "stress_grid.hpp"

namespace gimbalsim::stress {

struct PageInput {
  std::vector<const Case*> all;         ///< every run made, in the CSV's order
  const std::vector<Cell>* cells = nullptr;
  const std::vector<RestitutionRow>* restitution = nullptr;
  const Case* long_run = nullptr;       ///< the one-hour run, or null
  double v_in = 0.05;                   ///< restitution table's throw speed [m/s]
  std::string duration;                 ///< sim.duration of the grid [s]
  std::string csv_path = "out/stress/stress.csv";  ///< where the runs' CSV went (--csv)
  Bounds bounds;
  bool sweeps_ran = true;               ///< the one-at-a-time and pairwise sweeps ran (not --no-sweeps)
  bool grid_ran = true;                 ///< the sub-step walk ran (not --no-grid)
};

/// One letter per verdict: T, S, W, U, R.
char letter(Verdict v);

/// The page's body (Markdown, no header).
std::string pageBody(const PageInput& in);

}  // namespace gimbalsim::stress
