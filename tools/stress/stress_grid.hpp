// The stress grid's definition (issue 4): which runs it makes. One-at-a-time
// and pairwise sweeps of the paper scene's parameters, and the cells of the
// stiffness x clearance table, each a walk down a grid of sub-steps (or of
// the adaptive policy's tolerance) until the run is trustworthy. Running them
// is stress_run.hpp, the CSV stress_csv.hpp, the Markdown page stress_page.hpp.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "stress_check.hpp"

namespace gimbalsim::stress {

/// %g with `prec` significant digits (the grid's overrides and the page).
std::string num(double x, int prec = 3);
std::string joined(const std::vector<std::string>& v, const char* sep = " ");

/// One run of the grid.
struct Case {
  std::string group;              ///< sweep name
  std::string scene;              ///< scene file stem
  std::vector<std::string> sets;  ///< overrides
  Outcome out;
  bool ran = false;  ///< false: skipped after SIGINT/SIGTERM
};

/// The contact sub-step grid walked down from the control period.
extern const std::vector<double> kSubsteps;
extern const std::vector<double> kStiffness;
extern const std::vector<double> kClearance;
extern const std::vector<std::string> kDamping;
/// The adaptive policy's tolerances, walked down (Ambrosio friction: plain
/// Coulomb's sign flip defeats error control).
extern const std::vector<double> kTolerances;

/// One-at-a-time and pairwise sweeps (everything but the sub-step walk).
std::vector<Case> sweeps(const std::string& dur);

/// How a cell walks: the fixed contact sub-step under a 1 ms step, the step
/// itself (sim.step = sim.substep), or the adaptive policy's tolerance.
enum class Walk { Substep, WholeStep, Adaptive };
constexpr Walk kWalks[] = {Walk::Substep, Walk::WholeStep, Walk::Adaptive};

/// A cell of the stiffness x clearance table: a walk down one grid.
struct Cell {
  double stiffness = 1.0, clearance = 5e-4;
  Walk mode = Walk::Substep;
  std::vector<Case> walk;  ///< runs from the largest sub-step down to the first trustworthy
  int stable = -1;         ///< index in walk of the first trustworthy run, or -1
};

/// Every cell of the three tables, each with an empty walk.
std::vector<Cell> gridCells();
/// The values a cell's walk goes through, largest first.
const std::vector<double>& walkValues(Walk mode);
/// The run of a cell's walk at value h (sub-step, step or tolerance).
Case walkCase(const Cell& cell, double h, const std::string& dur);
/// The walked value of a run: its sim.substep or sim.substep_tol.
std::string walkedValue(const std::vector<std::string>& sets);

/// The one-hour run's overrides: its own, then --long-set's, each key once, with the place an error names
/// ("--long-set #k 'key=value'", or "the long run's own 'key=value'").
std::vector<std::pair<std::string, std::string>> longSets(const std::vector<std::string>& long_sets);
/// The one-hour run (--long-run) with these overrides after its own.
Case longCase(const std::string& scene, const std::vector<std::string>& long_sets);

/// Effective restitution of one impact per damping law (fixed base, no
/// friction, no torque, fine sub-step).
struct RestitutionRow {
  double ce = 0.0;
  std::map<std::string, double> eff;  ///< damping law -> effective c_e
};
/// The requested coefficients of the restitution table.
extern const std::vector<double> kRestitutions;
/// The overrides of one restitution measurement.
std::vector<std::string> restitutionSets(const std::string& law, double ce);

}  // namespace gimbalsim::stress
