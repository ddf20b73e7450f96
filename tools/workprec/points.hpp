// The work-precision sweep's points: a run's errors against the reference,
// the Pareto front, the cheapest point per accuracy, and the CSV.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "workprec.hpp"

namespace gimbalsim::workprec {

/// One point of the work-precision plot.
inline constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

struct Point {
  std::string scene, policy;
  double h = 0.0;                ///< outer step [s]
  // A point that did not run (refused, failed) has no figure: NaN, never 0 (docs/usage.md).
  double substep = kNoValue;     ///< sim.substep in effect [s]
  double event_tol = kNoValue;   ///< [s]
  std::string sweep_key, sweep_value;  ///< what this point of the curve varies
  bool ok = false;
  std::string note;              ///< why not ok
  double cpu_per_sim_s = kNoValue;  ///< median thread CPU s per simulated s
  int repeats = 0;
  double bore_err_max = kNoValue, bore_err_end = kNoValue;  ///< [rad]
  double theta1_err_max = kNoValue, theta2_err_max = kNoValue;  ///< [rad]
  double peak_force_err_rel = kNoValue;  ///< |peak - peak_ref| / peak_ref (NaN without contact)
  double momentum_drift_rel = kNoValue;  ///< NaN on a fixed base (the ground takes momentum)
  long long substeps = 0, impacts = 0;
  bool pareto = false;           ///< on the scene's Pareto front (cpu, bore_err_max)
};

/// Errors of a run against the reference at every output row; false (and a
/// note) when the rows do not line up.
bool compare(const Trajectory& run, const Trajectory& ref, Point& p);

/// Marks the points of each scene that no other ok point of that scene beats
/// in both CPU time and max boresight error.
void markPareto(std::vector<Point>& points);

/// The cheapest ok point of a scene with bore_err_max <= target, or nullptr.
const Point* cheapestFor(const std::vector<Point>& points, const std::string& scene, double target);

/// The CSV's text, with a header (kCsvColumns).
std::string csvText(const std::vector<Point>& points);
extern const std::vector<std::string> kCsvColumns;

}  // namespace gimbalsim::workprec
