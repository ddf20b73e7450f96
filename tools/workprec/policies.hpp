// The work-precision sweep's policies: the curves of the plot, each a set of
// scene overrides (tools/workprec/policies.yaml).
#pragma once

#include <string>
#include <vector>

namespace gimbalsim::workprec {

/// One curve of the plot: scene overrides applied on top of the scene.
struct Policy {
  std::string name;
  std::vector<std::string> sets;    ///< "key=value"; "{h}" and "{h}*k" expand
  bool contact_only = false;        ///< skipped on scenes without clearance
  std::string sweep_key;            ///< empty: the curve sweeps the outer step h
  std::vector<std::string> sweep_values;
};

/// Reads a policy table (tools/workprec/policies.yaml). Throws with file and
/// entry on a malformed table.
std::vector<Policy> loadPolicies(const std::string& path);

/// Expands "{h}" / "{h}*k" in one "key=value" override with the step h [s].
std::string expandSet(const std::string& set, double h);

}  // namespace gimbalsim::workprec
