// gimbalsim: command-line front end.
//   gimbalsim simulate SCENE [--set key=value]... --out run.csv [--summary s.json] [--check]
//   gimbalsim keys [--markdown]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <optional>

#include "gimbalsim/firmware_sim/plant_scene.hpp"
#include "gimbalsim/dynamics/simulate.hpp"
#include "gimbalsim/io/output_file.hpp"
#include "gimbalsim/run_output/run_output.hpp"
#include "gimbalsim/program/program.hpp"

namespace {

using gimbalsim::Row;

/// Writes rows as they come into the output's temporary, so a run that stops
/// keeps what it computed; the name appears when the run has ended.
class CsvWriter {
 public:
  CsvWriter(const std::string& path, const gimbalsim::ColumnSet& cols) : file_(path), cols_(cols) {
    file_.write(gimbalsim::io::csvHeader(cols_));
  }
  bool ok() const { return file_.ok(); }
  void write(const Row& r) {
    line_.clear();
    gimbalsim::io::appendCsvRow(line_, r, cols_);
    file_.write(line_);
  }
  gimbalsim::io::OutputFile& file() { return file_; }
  const std::string& error() const { return file_.error(); }

 private:
  gimbalsim::io::OutputFile file_;
  gimbalsim::ColumnSet cols_;  ///< the scene's columns (joint kinds)
  std::string line_;
};

// Exit codes: docs/usage.md "Exit codes" (program.hpp).
using gimbalsim::program::kOk;
using gimbalsim::program::kOutput;
using gimbalsim::program::kRefused;
using gimbalsim::program::kStopped;

int mainImpl(int argc, char** argv) {
  CLI::App app{"gimbalsim: two-axis antenna pointing mechanism on a free-floating satellite"};
  app.require_subcommand(1);

  auto* sim = app.add_subcommand("simulate", "run a scene and write a CSV (and a summary)");
  std::string scene, out, summary;
  std::vector<std::string> sets;
  sim->add_option("scene", scene, "scene file (YAML), e.g. tools/scenes/paper_clearance.yaml")->required();
  sim->add_option("--set", sets, "override a scene key: key=value (repeatable; see `gimbalsim keys`)");
  sim->add_option("--out", out, "CSV output path")->required();
  sim->add_option("--summary", summary, "summary JSON output path");
  std::string integrator = "rk4";
  sim->add_option("--integrator", integrator,
                  "rk4 (fixed step, sub-stepping, the product) or reference (adaptive Dormand-Prince 5(4), "
                  "tolerance 1e-12, for reference solutions)")
      ->check(CLI::IsMember({"rk4", "reference"}));
  bool check_only = false;
  sim->add_flag("--check", check_only,
                "check the scene, its overrides and the output paths as a run would; run and write nothing "
                "(exit 0 or 2)");

  auto* keys = app.add_subcommand("keys", "list every scene key with type, unit, default, check and meaning");
  bool markdown = false;
  keys->add_flag("--markdown", markdown, "as a Markdown table (the one in docs/scene_keys.md)");

  if (const auto rc = gimbalsim::program::parse(app, argc, argv, "gimbalsim")) return *rc;

  if (keys->parsed()) {
    const auto all = gimbalsim::firmware::plantTable().info();  // the scene's keys and its sensors'
    std::fputs((markdown ? gimbalsim::keysMarkdown(all) : gimbalsim::keysText(all)).c_str(), stdout);
    if (!markdown) {  // the Markdown table is the doc's; its aliases are listed beside it
      std::puts("\nold spellings, still read (docs/scene_keys.md):");
      const auto& aliases = gimbalsim::firmware::plantTable().aliases;
      int width = 0;  // the '=' of every line in one column
      for (const auto& [alias, key] : aliases) width = std::max(width, static_cast<int>(alias.size()));
      for (const auto& [alias, key] : aliases) std::printf("  %-*s = %s\n", width, alias.c_str(), key.c_str());
    }
    return kOk;
  }

  gimbalsim::Scene loaded;
  try {
    loaded = gimbalsim::firmware::loadPlantScene(scene, sets).scene;  // sensors.* accepted, unused here
  } catch (const gimbalsim::InputError& e) {
    return gimbalsim::program::refuse("gimbalsim", e);
  }
  // A scene file's sensors.* load (one file serves the bench), but a --set of one, checked as any key, would be
  // recorded with the run and act on nothing: no open-loop run reads a sensor (pass 86).
  for (std::size_t k = 0; k < sets.size(); ++k) {
    if (sets[k].rfind("sensors.", 0) != 0) continue;
    return gimbalsim::program::refuse("gimbalsim", "--set #" + std::to_string(k + 1) + " '" + sets[k] + "': an "
                                      "open-loop run reads no sensor (firmware_sim and the closed loop do): the value "
                                      "would be recorded but never act");
  }
  for (const auto& w : loaded.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  const gimbalsim::Model& m = loaded.model;
  if (integrator == "reference") {  // refused at once, not after seconds of crawling
    if (const std::string why = gimbalsim::referenceRefusal(m); !why.empty()) {
      return gimbalsim::program::refuse("gimbalsim", "--integrator reference: " + why);
    }
  }

  // Both outputs' temporaries exist from the start and commit together (CommitGroup).
  std::optional<CsvWriter> csv;
  std::optional<gimbalsim::io::OutputFile> summary_file;
  try {  // a path that cannot be an output (a folder, an input, no such folder): refused
    gimbalsim::io::checkOutputPaths({out, summary}, {scene});
  } catch (const gimbalsim::io::OutputError& e) {
    return gimbalsim::program::refuse("gimbalsim", e.what());
  }
  // A script running several scenes checks them all first: a refusal then costs none of the runs before it.
  if (check_only) {
    std::printf("gimbalsim: %s: accepted (nothing run, nothing written)\n", scene.c_str());
    return kOk;
  }
  try {  // a folder that takes no file (read-only, full): the exit-code table's "could not be written"
    csv.emplace(out, gimbalsim::io::outputColumns(m));
    if (!summary.empty()) summary_file.emplace(summary);
  } catch (const gimbalsim::io::OutputError& e) {
    return gimbalsim::program::unwritable("gimbalsim", e.what());
  }
  gimbalsim::io::installStopHandlers();
  // Checked after each row: a signal, or a CSV write that failed, ends the run there.
  const auto stop = [&] { return gimbalsim::io::stopRequested() || !csv->ok(); };
  gimbalsim::RunResult r = gimbalsim::simulate(
      loaded, [&](const Row& row) { csv->write(row); },
      integrator == "reference" ? gimbalsim::IntegratorKind::Reference : gimbalsim::IntegratorKind::Rk4, stop);
  const bool interrupted = r.stop.kind == gimbalsim::RunStop::Kind::Interrupted;
  if (interrupted) r.error += std::string(" by ") + gimbalsim::io::stopSignalName();
  if (summary_file) {
    nlohmann::json j = gimbalsim::io::runSummary(m, r, scene, integrator);
    j["overrides"] = sets;  // the run's --set, in order: a page or a reader says what the run was given (pass 50)
    summary_file->write(j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  }
  gimbalsim::io::CommitGroup outputs({&csv->file(), summary_file ? &*summary_file : nullptr});
  if (!outputs.commit()) {
    std::fprintf(stderr, "gimbalsim: error: %s\ngimbalsim: the run was stopped; no CSV and no summary written\n",
                 outputs.error().c_str());
    return kOutput;
  }
  // Sub-steps are the RK4's; the reference has none to report.
  const std::string substeps =
      r.integrator == gimbalsim::IntegratorKind::Rk4 ? std::to_string(r.stats.substeps) + " sub-steps, " : "";
  std::fprintf(stderr,
               "%s [%s]: %lld rows to t = %.6g s, %lld impacts, peak contact %.6g N, %swall %.3f s (stepping %.3f s)\n",
               m.name.c_str(), gimbalsim::variantName(m).c_str(), r.rows, r.t_end, r.stats.impacts,
               r.stats.peak_fn, substeps.c_str(), r.wall_seconds, r.step_seconds);
  if (!r.ok) {
    std::fprintf(stderr, "gimbalsim: %s%s\n", interrupted ? "" : "error: ", r.error.c_str());
    std::fprintf(stderr, "gimbalsim: the CSV holds the %lld good rows up to t = %.6g s\n", r.rows, r.t_end);
    return interrupted ? gimbalsim::io::stopExitCode() : kStopped;
  }
  return kOk;
}

}  // namespace

int main(int argc, char** argv) {
  return gimbalsim::program::guardedMain("gimbalsim", [&] { return mainImpl(argc, argv); });
}
