// gimbalsim: command-line front end.
//   gimbalsim simulate SCENE [--set key=value]... --out run.csv [--summary s.json]
//   gimbalsim keys [--markdown]
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "gimbalsim/dynamics/scene.hpp"
#include "gimbalsim/dynamics/simulate.hpp"

namespace {

using gimbalsim::Row;

/// Writes rows as they come, so a run that stops keeps what it computed.
class CsvWriter {
 public:
  explicit CsvWriter(const std::string& path) : f_(std::fopen(path.c_str(), "w")) {
    if (f_) {
      for (int i = 0; i < gimbalsim::kNumColumns; ++i) {
        std::fprintf(f_, "%s%s", i ? "," : "", gimbalsim::kColumns[i]);
      }
      std::fputc('\n', f_);
    }
  }
  ~CsvWriter() {
    if (f_) std::fclose(f_);
  }
  bool ok() const { return f_ != nullptr; }
  void write(const Row& r) {
    const double* p = gimbalsim::rowData(r);
    for (int i = 0; i < gimbalsim::kNumColumns; ++i) std::fprintf(f_, "%s%.12g", i ? "," : "", p[i]);
    std::fputc('\n', f_);
  }

 private:
  std::FILE* f_;
};

/// x, or null when `present` is false.
nlohmann::json valueOrNull(bool present, double x) {
  return present ? nlohmann::json(x) : nlohmann::json(nullptr);
}

nlohmann::json summaryJson(const gimbalsim::Model& m, const gimbalsim::RunResult& r,
                           const std::string& scene, const std::string& integrator_kind) {
  using nlohmann::json;
  const gimbalsim::RunStats& st = r.stats;
  auto named = [](const std::vector<std::string>& names, const std::vector<double>& values) {
    json o;
    for (size_t i = 0; i < values.size(); ++i) o[names[i]] = values[i];
    return o;
  };
  json j = {
      {"scene", scene},
      {"name", m.name},
      {"variant", gimbalsim::variantName(m)},
      {"status", r.ok ? "ok" : "failed"},
      {"t_end_s", r.t_end},
      {"rows", r.rows},
      {"impacts", st.impacts},
      {"separations", st.separations},
      {"peak_contact_force_N", st.peak_fn},
      {"t_peak_contact_force_s", valueOrNull(st.peak_fn > 0, st.t_peak_fn)},
      {"peak_joint2_force_N", r.peak_joint2_force},
      {"t_peak_joint2_force_s", r.t_peak_joint2_force},
      {"max_penetration_m", st.max_penetration},
      // Continuous contact: the contact that began at the last onset lasted to the end.
      {"continuous_contact_from_s",
       valueOrNull(m.clearance && r.in_contact_at_end && st.last_onset_time >= 0, st.last_onset_time)},
      {"final_state",
       {{"t", r.t_end},
        {"q", named(gimbalsim::coordinateNamesQ(m), r.final_q)},
        {"v", named(gimbalsim::coordinateNamesV(m), r.final_v)}}},
      {"momentum_drift",
       {{"linear_max_abs_Ns", r.max_drift_linear},
        {"angular_max_abs_Nms", r.max_drift_angular},
        {"angular_scale_Nms", r.momentum_scale},
        {"angular_relative", r.momentum_scale > 0 ? r.max_drift_angular / r.momentum_scale : 0.0}}},
      {"steps", st.steps},
      {"substeps", st.substeps},
      {"event_iterations", st.event_iterations},
      {"max_substeps_in_a_step", st.max_substeps_in_step},
      {"straddle_retries", st.straddle_retries},
      {"adaptive_rejected_substeps", st.rejected_substeps},
      {"adaptive_forced_substeps", st.forced_substeps},
      {"min_impact_duration_s", valueOrNull(st.min_impact_duration > 0, st.min_impact_duration)},
      {"wall_time_s", r.wall_seconds},
      {"step_time_s", r.step_seconds},
      {"integrator",
       {{"kind", integrator_kind},
        {"step_s", m.integrator.step},
        {"substep_s", m.integrator.substep},
        {"event_tol_s", m.integrator.event_tol}}}};
  if (!r.ok) {
    j["error"] = r.error;
    // What stopped the run, as codes: the scene key of the limit ("" when no
    // setting names it), the step status and the time.
    j["stop"] = {{"key", r.stop.key},
                 {"step_status", gimbalsim::describe(r.stop.step.status)},
                 {"time_s", r.stop.time}};
  }
  return j;
}

}  // namespace

int main(int argc, char** argv) {
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

  auto* keys = app.add_subcommand("keys", "list every scene key with type, unit, default, check and meaning");
  bool markdown = false;
  keys->add_flag("--markdown", markdown, "as a Markdown table (the one in README.md)");

  CLI11_PARSE(app, argc, argv);

  if (keys->parsed()) {
    const auto all = gimbalsim::sceneKeys();
    std::fputs((markdown ? gimbalsim::keysMarkdown(all) : gimbalsim::keysText(all)).c_str(), stdout);
    return 0;
  }

  gimbalsim::Scene loaded;
  try {
    loaded = gimbalsim::loadScene(scene, sets);
  } catch (const gimbalsim::SceneError& e) {
    for (const auto& p : e.problems()) std::fprintf(stderr, "error: %s\n", p.c_str());
    std::fprintf(stderr, "gimbalsim: scene refused, nothing simulated\n");
    return 2;
  }
  for (const auto& w : loaded.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  const gimbalsim::Model& m = loaded.model;

  CsvWriter csv(out);
  if (!csv.ok()) {
    std::fprintf(stderr, "error: cannot write %s\n", out.c_str());
    return 2;
  }
  const gimbalsim::RunResult r =
      gimbalsim::simulate(loaded, [&](const Row& row) { csv.write(row); },
                          integrator == "reference" ? gimbalsim::IntegratorKind::Reference
                                                    : gimbalsim::IntegratorKind::Rk4);

  if (!summary.empty()) {
    std::ofstream js(summary);
    if (!js) {
      std::fprintf(stderr, "error: cannot write %s\n", summary.c_str());
      return 2;
    }
    js << summaryJson(m, r, scene, integrator).dump(2) << "\n";
  }
  std::fprintf(stderr,
               "%s [%s]: %lld rows to t = %.6g s, %lld impacts, peak contact %.6g N, %lld sub-steps, "
               "wall %.3f s (stepping %.3f s)\n",
               m.name.c_str(), gimbalsim::variantName(m).c_str(), r.rows, r.t_end, r.stats.impacts,
               r.stats.peak_fn, r.stats.substeps, r.wall_seconds, r.step_seconds);
  if (!r.ok) {
    std::fprintf(stderr, "error: %s\n", r.error.c_str());
    std::fprintf(stderr, "gimbalsim: the CSV holds the %lld good rows up to t = %.6g s\n", r.rows, r.t_end);
    return 3;
  }
  return 0;
}
