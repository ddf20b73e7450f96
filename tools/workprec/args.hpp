// gimbalsim_workprec's command line: the options, their ranges and the checks
// made before anything runs (the policy table, the output folder, the CSV's and
// the reference caches' paths).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "policies.hpp"

#ifndef GIMBALSIM_SCENES_DIR
#define GIMBALSIM_SCENES_DIR "tools/scenes"
#endif
#ifndef GIMBALSIM_WORKPREC_DIR
#define GIMBALSIM_WORKPREC_DIR "tools/workprec"
#endif

namespace gimbalsim::workprec {

/// The sweep's settings (its command line).
struct Args {
  // paper_both_spatial is chaotic (docs/MODEL.md 2.7): no error to a reference past a fraction of a second.
  std::vector<std::string> scenes = {"paper_ideal", "paper_ideal_valid_inertia", "paper_clearance",
                                     "stickslip_clearance", "paper_both_planar", "paper_spatial2"};
  std::string scenes_dir = GIMBALSIM_SCENES_DIR;
  std::string policies_path = std::string(GIMBALSIM_WORKPREC_DIR) + "/policies.yaml";
  std::vector<double> steps = {2e-2, 1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4};
  std::vector<std::string> extra_sets, only_policies;
  int repeats = 3;
  double duration = 0.0, output_interval = 2e-2, peak_dt = 1e-6, max_run_seconds = 3.0;
  std::string out_dir = "out/workprec";
  bool quick = false, no_mujoco = false;
  std::vector<Policy> policies;  ///< the table, cut to --policy
};

/// Parses and checks argv into a: nullopt to go on, else the exit code
/// (0 after --help, 2 for a refusal, printed).
std::optional<int> parseArgs(int argc, char** argv, Args& a);
/// The file of a --scenes name: <--scenes-dir>/<name>.yaml.
inline std::string scenePath(const Args& a, const std::string& scene) { return a.scenes_dir + "/" + scene + ".yaml"; }

}  // namespace gimbalsim::workprec
