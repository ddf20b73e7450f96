#include "args.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <filesystem>
#include <utility>

#include "gimbalsim/input/value_format.hpp"
#include "gimbalsim/io/output_file.hpp"
#include "gimbalsim/program/program.hpp"

namespace gimbalsim::workprec {

namespace {

/// A reference cache (ref_*.csv in the output folder) that is a link, a folder
/// or a device: refused before anything runs, as the CSV's name is; "" if none.
std::string cacheEntryProblem(const std::string& out_dir) {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(out_dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("ref_", 0) != 0 || name.size() < 8 || name.compare(name.size() - 4, 4, ".csv") != 0) continue;
    const auto st = entry.symlink_status(ec);
    if (!ec && !std::filesystem::is_regular_file(st)) {
      return entry.path().string() + ": a reference cache must be a regular file (a link, folder or device is refused)";
    }
  }
  return "";
}

}  // namespace

/// Parse: the options, checked; nullopt to go on, else the exit code.
std::optional<int> parseArgs(int argc, char** argv, Args& a) {
  CLI::App app{"gimbalsim work-precision sweep: CPU time per simulated second against error to a reference"};
  app.add_option("--scenes", a.scenes, "scene names in the scenes directory")->delimiter(',');
  app.add_option("--scenes-dir", a.scenes_dir, "where the scene files are");
  app.add_option("--policies", a.policies_path, "policy table (YAML)");
  app.add_option("--policy", a.only_policies, "only these policies (by name; repeatable)");
  app.add_option("--steps", a.steps, "outer steps h [s] swept by the plain curves")
      ->delimiter(',')->check(program::within(1e-9, 1e3));  // below 1 ns no scene steps (and --output-interval was blamed)
  app.add_option("--repeats", a.repeats, "timed runs per point (the median is reported)")
      ->check(program::wholeNumber())
      ->check(CLI::Range(1, 99));
  app.add_option("--duration", a.duration, "simulated time [s] (default: the scenes')")
      ->check(program::within(0.0, 1e6, true));
  app.add_option("--output-interval", a.output_interval, "row spacing the errors are compared at [s]")
      ->check(program::within(0.0, 1e6, true));
  app.add_option("--peak-dt", a.peak_dt, "sampling of the reference's peak contact force [s]")
      ->check(program::within(1e-9, 1e3));
  app.add_option("--max-run-seconds", a.max_run_seconds,
                 "end a curve after a point whose run takes longer than this [CPU s]")
      ->check(program::within(0.0, 1e9, true));
  app.add_option("--set", a.extra_sets, "key=value applied to every scene (repeatable)");
  app.add_option("--out", a.out_dir, "output directory (CSV, reference cache)");
  app.add_flag("--quick", a.quick, "a few short points (smoke test): 1 s, h = 0.04, 0.02, 0.01, rows every 0.04 s");
  app.add_flag("--no-mujoco", a.no_mujoco, "skip the MuJoCo peer even when built with it");
  if (const auto rc = program::parse(app, argc, argv, "gimbalsim_workprec")) return *rc;
  if (a.quick && (app.count("--steps") || app.count("--output-interval"))) {  // --quick would overwrite them
    return program::refuse("gimbalsim_workprec", "--quick sets --steps and --output-interval: give one or the other");
  }
  if (a.quick) {
    a.steps = {4e-2, 2e-2, 1e-2};
    a.output_interval = 4e-2;
    if (a.duration <= 0.0) a.duration = 1.0;
    // its default is coarser for speed; a --peak-dt the user gives is theirs (pass 81: 1e-6 ran at 1e-5)
    if (!app.count("--peak-dt")) a.peak_dt = std::max(a.peak_dt, 1e-5);
  }
  // Counts derived from these (reference samples, rows) must fit a long long: refused with exit 2.
  // (--duration has its own range above; 0, the default, is the scenes' own)
  if (!(a.peak_dt > 0.0 && a.output_interval >= a.peak_dt && a.output_interval / a.peak_dt <= 1e9)) {
    return program::refuse("gimbalsim_workprec", "need 0 < --peak-dt <= --output-interval <= 1e9 --peak-dt");
  }
  // One point is one curve's run: a scene or step given twice ran twice, two identical rows (pass 73); a scene
  // is one file whatever its spelling (pass 76: paper_ideal and ./paper_ideal).
  for (std::size_t i = 0; i < a.scenes.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      std::error_code ec;
      if (a.scenes[i] == a.scenes[j] || std::filesystem::equivalent(scenePath(a, a.scenes[i]),
                                                                    scenePath(a, a.scenes[j]), ec)) {
        return program::refuse("gimbalsim_workprec", "--scenes: " + a.scenes[i] +
                                                         (a.scenes[i] == a.scenes[j] ? "" : " (" + a.scenes[j] + ")") +
                                                         " given twice");
      }
    }
  }
  for (const auto& why : {program::repeatedValue("--steps", a.steps), program::repeatedValue("--policy",
                                                                                            a.only_policies)}) {
    if (!why.empty()) return program::refuse("gimbalsim_workprec", why);
  }
  // Every point runs whole steps h (the scene's own rule): a duration or row spacing between two is
  // refused here, once, not recorded as every point refused.
  for (const double h : a.steps) {
    for (const auto& [flag, value] : {std::pair{"--duration", a.duration}, {"--output-interval", a.output_interval}}) {
      if (value <= 0.0) continue;  // --duration 0: the scenes' own
      if (const std::string why = wholeMultipleProblem(value, h, "the step h = " + formatNumber(h)); !why.empty()) {
        return program::refuse("gimbalsim_workprec", std::string(flag) + ": " + why);
      }
    }
  }
  try {
    a.policies = loadPolicies(a.policies_path);
  } catch (const std::exception& e) {
    return program::refuse("gimbalsim_workprec", e.what());
  }
  for (const std::string& name : a.only_policies) {  // a --policy the table does not hold is refused, never ignored
    if (std::none_of(a.policies.begin(), a.policies.end(), [&](const Policy& p) { return p.name == name; })) {
      return program::refuse("gimbalsim_workprec", "--policy " + name + ": no such policy in " + a.policies_path);
    }
  }
  if (!a.only_policies.empty()) {
    std::erase_if(a.policies, [&](const Policy& p) {
      return std::find(a.only_policies.begin(), a.only_policies.end(), p.name) == a.only_policies.end();
    });
  }
  if (const std::string why = gimbalsim::io::outputFolderProblem(a.out_dir, app.count("--out") > 0); !why.empty()) {
    return program::refuse("gimbalsim_workprec", "--out " + a.out_dir + ": " + why);
  }
  // The CSV is checked before anything runs: a link under its name, or the policy table or a scene
  // under it (it was overwritten with the results), is refused, not found at the end.
  std::vector<std::string> inputs{a.policies_path};
  for (const std::string& scene : a.scenes) inputs.push_back(scenePath(a, scene));
  try {
    gimbalsim::io::checkOutputPaths({a.out_dir + "/workprec.csv"}, inputs);
  } catch (const gimbalsim::io::OutputError& e) {
    return program::refuse("gimbalsim_workprec", std::string("--out: ") + e.what());
  }
  if (const std::string why = cacheEntryProblem(a.out_dir); !why.empty()) {
    return program::refuse("gimbalsim_workprec", "--out: " + why);
  }
  return std::nullopt;
}

}  // namespace gimbalsim::workprec
