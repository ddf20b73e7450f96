// gimbalsim_stress: the numerical stability stress grid of issue 4.
//
// Sweeps contact stiffness, clearance, joint torques, restitution with each
// damping law, the friction law and the step size, one at a time and in pairs,
// and classifies every run (stress_check.hpp): TRUSTWORTHY, STOPPED with a
// diagnostic naming the limit, or a failure (SILENTLY_WRONG, STOPPED_UNCLEAR,
// REFUSED), which makes the exit status 1. For each contact stiffness and
// clearance it walks the contact sub-step down a grid until the run is
// trustworthy and tabulates the largest such sub-step and what it costs.
//
// The grid: stress_grid.hpp; running it: stress_run.hpp; the CSV (one row per
// run): stress_csv.hpp; the Markdown body of docs/results/stress.md
// (--page-body, or --markdown to stdout): stress_page.hpp. The page with its
// header is written by tools/stress/run_stress.sh; this program never edits
// README.md.
#include <cmath>
#include <CLI/CLI.hpp>

#include <chrono>
#include <filesystem>
#include <cstdio>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "gimbalsim/firmware_sim/plant_scene.hpp"
#include "gimbalsim/input/input_error.hpp"
#include "gimbalsim/io/output_file.hpp"
#include "gimbalsim/scene/scene.hpp"
#include "gimbalsim/program/program.hpp"
#include "gimbalsim/program/stop_signal.hpp"
#include "stress_csv.hpp"
#include "stress_grid.hpp"
#include "stress_page.hpp"
#include "stress_run.hpp"

namespace st = gimbalsim::stress;
namespace io = gimbalsim::io;

namespace {

/// Prints the counts; with failures, lists them. Returns the number of failures.
int report(const std::vector<const st::Case*>& all, double wall) {
  int failures = 0;
  std::map<std::string, int> count;
  for (const st::Case* c : all) {
    ++count[st::verdictName(c->out.verdict)];
    if (!st::acceptable(c->out.verdict)) ++failures;
  }
  std::printf("\n%zu runs in %.1f s wall:", all.size(), wall);
  for (const auto& [k, n] : count) std::printf(" %s %d", k.c_str(), n);
  std::printf("\n");
  if (failures > 0) {
    const int refused = count["REFUSED"];  // (pass 46) a scene changed during the study: not "wrong"
    std::printf("\n*** %d FAILING RUN(S): %d finished without a diagnostic but wrong, or stopped unclearly; "
                "%d refused by their scene ***\n", failures, failures - refused, refused);
    for (const st::Case* c : all) {
      if (!st::acceptable(c->out.verdict)) {
        std::printf("  %s  %s --set %s\n    %s\n", st::verdictName(c->out.verdict), c->scene.c_str(),
                    st::joined(c->sets, " --set ").c_str(), c->out.reason.c_str());
      }
    }
  }
  return failures;
}

void printLong(const st::Case& c) {
  const st::Outcome& o = c.out;
  std::printf("long run: %s, %.1f s simulated in %.1f s wall (%.1f s stepping), %lld impacts, "
              "%.3g sub-steps/s, momentum drift P %.3g L %.3g (relative), energy balance: max rise %.3g, "
              "final change %.3g (relative)\n",
              st::verdictName(o.verdict), o.run.t_end, o.run.wall_seconds, o.run.step_seconds, o.run.stats.impacts,
              o.substeps_per_second, o.momentum_rel_linear, o.momentum_rel_angular, o.energy_rise_rel,
              o.energy_final_rel);
}

/// Refused before anything runs (exit 2): a scenes folder that is not one,
/// the scenes of --case and of the long run with their overrides (loaded
/// here, so a refusal names key and place), and an output that is an input.
/// need_scenes: false when every scene that runs is given by path (--case, --long-scene).
void checkInputs(const std::string& scenes, bool need_scenes, const std::vector<std::string>& scene_paths,
                 const std::vector<std::vector<std::string>>& sets, const std::vector<std::vector<std::string>>& labels,
                 const std::vector<std::string>& outputs) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (need_scenes && !fs::is_directory(scenes, ec)) throw gimbalsim::InputError("--scenes " + scenes + ": not a folder");
  std::vector<std::string> inputs = scene_paths;
  for (const auto& e : fs::directory_iterator(scenes, ec)) {
    if (e.path().extension() == ".yaml") inputs.push_back(e.path().string());
  }
  for (std::size_t i = 0; i < scene_paths.size(); ++i) {
    try {
      const gimbalsim::Scene sc = gimbalsim::firmware::loadPlantScene(scene_paths[i], sets[i]).scene;
      // a --case's --set the scene leaves idle is said, as gimbalsim simulate says it (pass 93: base.mass on a
      // fixed base was printed as applied with no word)
      for (const std::string& w : sc.warnings) {
        if (labels[i].empty() && !sets[i].empty()) std::fprintf(stderr, "gimbalsim_stress: warning: %s\n", w.c_str());
      }
    } catch (const gimbalsim::InputError& e) {  // an override named by the flag the user gave (pass 50: "--set #3")
      if (labels[i].empty()) throw;
      throw gimbalsim::InputError(gimbalsim::relabelledProblems(e, labels[i]));
    }
  }
  try {
    io::checkOutputPaths(outputs, inputs);
  } catch (const io::OutputError& e) {
    throw gimbalsim::InputError(e.what());
  }
}

/// Every run the study will make (sweeps, grid walks, the restitution table), loaded with its overrides before
/// any runs (pass 45: a bad paper_spatial2.yaml ran the study and ended exit 1 with REFUSED rows). A scene file
/// that cannot be read is named first, alone; then a run whose overrides its scene refuses, by group and sets.
void checkStudyRuns(const std::string& scenes, const std::string& dur, bool sweeps, bool grid) {
  std::vector<st::Case> runs;
  if (sweeps) {
    runs = st::sweeps(dur);
    for (const auto& law : st::kDamping) {
      for (double ce : st::kRestitutions) runs.push_back({"restitution table", "paper_clearance",
                                                          st::restitutionSets(law, ce), {}});
    }
  }
  if (grid) {
    for (const st::Cell& cell : st::gridCells()) {
      for (double h : st::walkValues(cell.mode)) runs.push_back(st::walkCase(cell, h, dur));
    }
  }
  std::map<std::string, bool> read;  // scene file -> loaded bare
  for (const st::Case& c : runs) {
    if (const std::string path = st::scenePath(scenes, c.scene); !read[path]) {
      gimbalsim::firmware::loadPlantScene(path);  // throws InputError naming the file, key and line
      read[path] = true;
    }
  }
  for (const st::Case& c : runs) {
    try {
      gimbalsim::firmware::loadPlantScene(st::scenePath(scenes, c.scene), c.sets);
    } catch (const gimbalsim::InputError& e) {
      std::vector<std::string> texts;
      for (const std::string& p : e.problems()) {
        texts.push_back("the study's " + c.group + " run (" + st::joined(c.sets) + ") refused by its scene: " + p);
      }
      throw gimbalsim::InputError(texts);
    }
  }
}

int mainImpl(int argc, char** argv) {
  CLI::App app{"gimbalsim_stress: numerical stability stress grid"};
  std::string scenes = "tools/scenes", csv = "out/stress/stress.csv", page_body, dur = "1";
  std::string long_scene = "paper_clearance";
  // The hour: no torque (a constant torque would spin the shafts up without
  // bound), both joints turning, Ambrosio friction; the journal settles into
  // continuous contact. The adaptive policy at 1e-8 (trustworthy on this
  // scene in the grid) keeps it under a minute; --long-set replaces the list
  // (e.g. the fixed sub-step 2e-5 takes about 16 CPU minutes).
  std::vector<std::string> long_sets = {"torque.tau1=0", "torque.tau2=0", "initial.dtheta1=0.5",
                                        "initial.dtheta2=-0.3", "friction.law=ambrosio",
                                        "sim.substep_policy=adaptive", "sim.substep_tol=1e-8"};
  int threads = 2;
  bool md = false, no_grid = false, no_sweeps = false, long_run = false, long_only = false;
  st::Bounds b;
  double v_in = 0.05;
  app.add_option("--scenes", scenes, "scene directory");
  app.add_option("--csv", csv, "CSV of every run");
  // kept as the text the scene reads, checked as every real flag is (pass 43: 00.05 ran)
  app.add_option("--duration", dur, "simulated time of each run [s]")->type_name("FLOAT");
  app.add_option("--threads", threads, "runs in parallel (at most 2 on this machine)")
      ->check(gimbalsim::program::wholeNumber())
      ->check(CLI::Range(1, 2));
  // A bound of 0 or below would call every run SILENTLY_WRONG (exit 1, "a bug"), and so would one below a
  // double's round-off (pass 71: 1e-300 called a trustworthy run a bug): at least 1e-12 of the scale.
  app.add_option("--momentum-bound", b.momentum_rel, "relative momentum drift bound, in [1e-12, 1]")
      ->check(gimbalsim::program::within(1e-12, 1.0));
  app.add_option("--energy-bound", b.energy_rel, "relative energy rise bound, in [1e-12, 1]")
      ->check(gimbalsim::program::within(1e-12, 1.0));
  app.add_flag("--markdown", md, "print the results page's body (Markdown) to stdout");
  app.add_option("--page-body", page_body,
                 "write the results page's body (Markdown) to this file; tools/stress/run_stress.sh adds the "
                 "header and writes docs/results/stress.md");
  app.add_flag("--no-grid", no_grid, "skip the sub-step walk over stiffness x clearance");
  app.add_flag("--no-sweeps", no_sweeps, "skip the one-at-a-time and pairwise sweeps");
  app.add_flag("--long-run", long_run, "also run one simulated hour (about 30 s of wall time)");
  app.add_flag("--long-run-only", long_only, "run only the one-hour run");
  app.add_option("--long-scene", long_scene, "scene of the long run");
  app.add_option("--long-set", long_sets, "overrides of the long run (repeatable; replace the default list)");
  std::string one_scene;
  std::vector<std::string> one_sets;
  app.add_option("--case", one_scene, "classify one run of this scene (stem or path) and exit");
  app.add_option("--set", one_sets, "override of --case (repeatable)");
  if (const auto rc = gimbalsim::program::parse(app, argc, argv, "gimbalsim_stress")) return *rc;
  // --case classifies one run and writes nothing: a flag of the study it skips would be ignored.
  if (!one_scene.empty()) {
    for (const char* f : {"--csv", "--page-body", "--markdown", "--no-grid", "--no-sweeps", "--long-run",
                          "--long-run-only", "--long-scene", "--long-set", "--threads"}) {
      if (app.count(f)) {
        return gimbalsim::program::refuse("gimbalsim_stress", std::string(f) + ": --case runs one scene and writes "
                                                              "nothing; this flag is the study's (drop --case)");
      }
    }
  } else if (app.count("--set")) {
    return gimbalsim::program::refuse("gimbalsim_stress", "--set: only --case reads it (the study's runs take "
                                                          "--long-set or --duration)");
  }
  // (pass 101) a sensor key was "unknown key (see `gimbalsim keys`)", which lists it: refused as simulate does
  // (pass 105: --long-set alike)
  for (const auto& [flag, given] : {std::pair{"--set", &one_sets}, std::pair{"--long-set", &long_sets}}) {
    for (std::size_t k = 0; k < given->size(); ++k) {
      if ((*given)[k].rfind("sensors.", 0) != 0) continue;
      return gimbalsim::program::refuse("gimbalsim_stress", std::string(flag) + " #" + std::to_string(k + 1) + " '" +
                                                                (*given)[k] + "': an open-loop run reads no sensor "
                                                                "(firmware_sim and the closed loop do): the value "
                                                                "would be recorded but never act");
    }
  }
  if (one_scene.empty()) {
    // Flags of the long run with no long run asked for were dropped without a word (pass 68), and the two
    // long-run flags together ran one of them.
    if (long_run && long_only) {
      return gimbalsim::program::refuse("gimbalsim_stress", "--long-run and --long-run-only: give one (--long-run adds "
                                                            "the hour to the study, --long-run-only runs it alone)");
    }
    // (pass 117) and the two skips beside the mode that runs neither, accepted as if they did something
    for (const char* f : {"--no-grid", "--no-sweeps"}) {
      if (app.count(f) && long_only) {
        return gimbalsim::program::refuse("gimbalsim_stress", std::string(f) + ": --long-run-only runs neither the "
                                                              "grid nor the sweeps; give one of the two");
      }
    }
    for (const char* f : {"--long-scene", "--long-set"}) {
      if (app.count(f) && !long_run && !long_only) {
        return gimbalsim::program::refuse("gimbalsim_stress", std::string(f) + ": only the long run reads it; add "
                                                              "--long-run or --long-run-only");
      }
    }
  }
  if (long_only) no_grid = no_sweeps = long_run = true;
  // A study of nothing would exit 0 with a page and no result (pass 55): refused, naming the flags.
  if (one_scene.empty() && no_grid && no_sweeps && !long_run) {
    return gimbalsim::program::refuse("gimbalsim_stress", "--no-grid --no-sweeps: nothing left to run (add "
                                                          "--long-run, or drop one of them)");
  }
  // --duration is the sweeps' and the grid's: a run that has neither would ignore it.
  if (app.count("--duration") && (!one_scene.empty() || (no_sweeps && no_grid))) {
    return gimbalsim::program::refuse(
        "gimbalsim_stress", "--duration " + dur + ": only the sweeps and the grid read it; " +
                                (one_scene.empty() ? std::string("this run has neither")
                                                   : "--case runs its scene's sim.duration (--set sim.duration=S)"));
  }
  // An output folder named on the command line must exist (refused below); only the default one is made.
  // (--case writes no CSV: it makes no folder.)
  // A refusal below leaves no folder it made (pass 44: an empty out/stress/ was left): removed if still empty
  // when main returns before the runs start.
  struct MadeFolder {
    std::filesystem::path dir, top;  // the folder, and the outermost one made for it
    bool keep = false;
    ~MadeFolder() {
      std::error_code ec;  // remove() refuses a folder that is not empty: only what is still empty goes
      for (auto p = dir; !keep && !top.empty() && std::filesystem::remove(p, ec) && p != top;) p = p.parent_path();
    }
  } made;
  if (std::error_code ec; !app.count("--csv") && one_scene.empty()) {
    made.dir = std::filesystem::path(csv).parent_path();
    for (auto p = made.dir; !p.empty() && !std::filesystem::exists(p, ec); p = p.parent_path()) made.top = p;
    std::filesystem::create_directories(made.dir, ec);
  }
  {
    std::vector<std::string> paths, outputs;
    std::vector<std::vector<std::string>> sets, labels;  // labels: the places an error names ({}: --set's own)
    if (!one_scene.empty()) {
      paths.push_back(st::scenePath(scenes, one_scene));
      sets.push_back(one_sets);
      labels.emplace_back();
    } else {
      if (long_run) {
        paths.push_back(st::scenePath(scenes, long_scene));
        sets.push_back(st::longCase(long_scene, long_sets).sets);
        labels.emplace_back();
        for (const auto& [set, label] : st::longSets(long_sets)) labels.back().push_back(label);
      }
      for (const std::string& o : {csv, page_body}) {
        if (!o.empty()) outputs.push_back(o);
      }
    }
    const auto stem = st::isSceneStem;
    const bool need_scenes = one_scene.empty() ? !no_sweeps || !no_grid || (long_run && stem(long_scene)) : stem(one_scene);
    checkInputs(scenes, need_scenes, paths, sets, labels, outputs);
  }
  // Every sweep and grid run is paper_clearance with sim.duration = --duration:
  // a duration the scene refuses is refused here, once, naming the flag.
  if (one_scene.empty() && (!no_sweeps || !no_grid)) {
    // the file's own fault is not --duration's
    gimbalsim::firmware::loadPlantScene(st::scenePath(scenes, "paper_clearance"));
    try {
      gimbalsim::firmware::loadPlantScene(st::scenePath(scenes, "paper_clearance"), {"sim.duration=" + dur});
    } catch (const gimbalsim::InputError& e) {
      std::string why = e.problems().empty() ? e.what() : e.problems().front();
      const auto at = why.find("': ");  // drop the "--set #1 '...'" place: the flag is named instead
      if (why.rfind("--set #", 0) == 0 && at != std::string::npos) why.erase(0, at + 3);
      return gimbalsim::program::refuse("gimbalsim_stress", "--duration " + dur + ": " + why);
    }
  }
  if (one_scene.empty()) checkStudyRuns(scenes, dur, !no_sweeps, !no_grid);
  made.keep = true;  // checked: the runs start
  if (!one_scene.empty()) {
    st::Case c{"case", one_scene, one_sets, {}};
    c.out = st::runCase(st::scenePath(scenes, one_scene), one_sets, b);
    st::printCase(c);
    std::printf("impacts %lld, sub-steps %lld, ", c.out.run.stats.impacts, c.out.run.stats.substeps);
    if (std::isnan(c.out.energy_change_rel)) {  // a bare "nan (final nan)" read as a figure (pass 84)
      std::printf("energy balance change n/a (the run stopped in its first step: no good state after t = 0 s)\n");
    } else {
      std::printf("energy balance change %.3g (final %.3g) relative to the energy scale\n", c.out.energy_change_rel,
                  c.out.energy_final_rel);
    }
    return st::acceptable(c.out.verdict) ? 0 : 1;
  }
  // SIGINT/SIGTERM: cases running finish, the rest are skipped, the CSV holds the whole cases.
  io::installStopHandlers();

  const auto t0 = std::chrono::steady_clock::now();
  std::vector<const st::Case*> all;
  std::vector<st::Case> sw;
  if (!no_sweeps) {
    sw = st::sweeps(dur);
    st::runSweeps(sw, scenes, threads, b);
    for (const auto& c : sw) {
      if (c.ran) all.push_back(&c);
    }
  }
  std::vector<st::Cell> cells;
  if (!no_grid) {
    cells = st::gridCells();
    st::runGrid(cells, scenes, dur, threads, b);
    for (const auto& cell : cells) {
      for (const auto& c : cell.walk) all.push_back(&c);
    }
  }
  std::vector<st::Case> longc;
  if (long_run && !io::stopRequested()) {
    longc.push_back(st::longCase(long_scene, long_sets));
    st::runCase(longc[0], scenes, b);
    printLong(longc[0]);
    all.push_back(&longc[0]);
  }
  // The CSV and the page commit together (io::CommitGroup); an interrupted run writes the CSV alone.
  auto write = [&](bool with_page, const std::string& body) {
    std::vector<std::pair<std::string, std::string>> files;
    if (!csv.empty() && !all.empty()) {
      if (const auto dir = std::filesystem::path(csv).parent_path(); !dir.empty()) std::filesystem::create_directories(dir);
      files.emplace_back(csv, st::csvText(all));
    }
    if (with_page && !page_body.empty()) files.emplace_back(page_body, body);
    try {
      io::writeFilesTogether(files);
    } catch (const std::exception& e) {  // io::OutputError, or the directory not creatable
      std::cerr << "error: " << e.what() << "\n";
      return false;
    }
    return true;
  };
  if (io::stopRequested()) {
    if (!write(false, "")) return gimbalsim::program::kOutput;
    std::fprintf(stderr, "gimbalsim_stress: interrupted by %s after %zu whole runs (in the CSV); no page written\n",
                 io::stopSignalName(), all.size());
    return io::stopExitCode();
  }

  std::vector<st::RestitutionRow> rest;
  bool rest_refused = false;
  try {
    if (!no_sweeps) rest = st::restitutionTable(scenes, v_in);
  } catch (const gimbalsim::InputError& e) {  // (pass 49) a scene edited during the study: its runs' CSV is kept
    std::fprintf(stderr, "gimbalsim_stress: the restitution table is not measured (its scene refused it): %s\n",
                 e.what());
    rest_refused = true;
  }
  st::PageInput page{all, &cells, &rest, longc.empty() ? nullptr : &longc[0], v_in, dur, csv, b, !no_sweeps, !no_grid};
  const std::string body = st::pageBody(page);
  if (md) std::cout << "\n" << body;
  if (!write(true, body)) return gimbalsim::program::kOutput;
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report(all, wall) > 0 || rest_refused ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  return gimbalsim::program::guardedMain("gimbalsim_stress", [&] { return mainImpl(argc, argv); });
}
