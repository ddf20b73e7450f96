// What a run writes: the CSV text of its rows and its summary JSON. One
// formatter for the command line and the Python package, so both write the
// same bytes for the same scene.
#pragma once

#include <nlohmann/json.hpp>
#include <span>
#include <string>

#include "gimbalsim/dynamics/observables.hpp"
#include "gimbalsim/dynamics/simulate.hpp"

namespace gimbalsim::io {

/// The columns a run of this model writes (observables.hpp, outputColumns).
inline ColumnSet outputColumns(const Model& m) { return gimbalsim::outputColumns(m.joint1_kind, m.joint2_kind); }

/// The CSV header line: each column of `cols` with its unit (io::csvName),
/// joined by ',', then '\n'.
std::string csvHeader(const ColumnSet& cols);

/// Appends the columns `cols` of one full row (kNumColumns values, in Row
/// order; io::appendCsvNumber each) and '\n' to `out`.
void appendCsvRow(std::string& out, std::span<const double, kNumColumns> row, const ColumnSet& cols);
inline void appendCsvRow(std::string& out, const Row& r, const ColumnSet& cols) {
  appendCsvRow(out, std::span<const double, kNumColumns>(rowData(r), kNumColumns), cols);
}

/// The summary of a run, as `gimbalsim simulate --summary` writes it (dump(2)).
/// `scene` is the scene file as given; `integrator_kind` "rk4" or "reference".
nlohmann::json runSummary(const Model& m, const RunResult& r, const std::string& scene,
                          const std::string& integrator_kind);

}  // namespace gimbalsim::io
