// gimbalsim_stress: the numerical stability stress grid of issue 4.
//
// Sweeps contact stiffness, clearance, joint torques, restitution with each
// damping law, the friction law and the step size, one at a time and in pairs,
// and classifies every run (stress_check.hpp): TRUSTWORTHY, STOPPED with a
// diagnostic naming the limit, or a failure (SILENTLY_WRONG, STOPPED_UNCLEAR,
// REFUSED), which makes the exit status 1. For each contact stiffness and
// clearance it walks the contact sub-step down a grid until the run is
// trustworthy and tabulates the largest such sub-step and what it costs.
// Writes a CSV (one row per run) and, with --markdown / --update-readme, the
// README table.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "gimbalsim/scene/scene.hpp"
#include "gimbalsim/io/output_file.hpp"
#include "gimbalsim/program/stop_signal.hpp"
#include "stress_check.hpp"

namespace gs = gimbalsim;
namespace st = gimbalsim::stress;

namespace {

std::string num(double x, int prec = 3) {
  std::ostringstream os;
  os.precision(prec);
  os << x;
  return os.str();
}

/// One run of the grid.
struct Case {
  std::string group;              ///< sweep name
  std::string scene;              ///< scene file stem
  std::vector<std::string> sets;  ///< overrides
  st::Outcome out;
  bool ran = false;  ///< false: skipped after SIGINT/SIGTERM
};

std::string joined(const std::vector<std::string>& v, const char* sep = " ") {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : sep) + x;
  return s;
}

/// The contact sub-step grid walked down from the control period.
const std::vector<double> kSubsteps = {1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5, 5e-6, 2e-6, 1e-6};
const std::vector<double> kStiffness = {0.01, 0.1, 1.0, 10.0, 100.0};
const std::vector<double> kClearance = {5e-6, 5e-5, 5e-4, 5e-3};
const std::vector<std::string> kDamping = {"hunt_crossley", "lankarani_nikravesh", "flores"};

/// One-at-a-time and pairwise sweeps (everything but the sub-step walk).
std::vector<Case> sweeps(const std::string& dur) {
  std::vector<Case> c;
  const std::string D = "sim.duration=" + dur;
  auto add = [&](const std::string& g, const std::string& scene, std::vector<std::string> sets) {
    sets.insert(sets.begin(), D);
    c.push_back({g, scene, std::move(sets), {}});
  };
  for (double k : kStiffness) add("stiffness", "paper_clearance", {"contact.stiffness_scale=" + num(k)});
  for (double cl : kClearance) add("clearance", "paper_clearance", {"contact.clearance=" + num(cl)});
  for (double x : {0.1, 1.0, 5.0, 20.0}) {
    add("torque", "paper_clearance", {"torque.tau1=" + num(5.0 * x), "torque.tau2=" + num(10.0 * x)});
  }
  for (const char* scene : {"paper_ideal", "planar_ideal"}) {
    add("torque", scene, {"torque.tau1=100", "torque.tau2=200"});
  }
  for (const auto& law : kDamping) {
    for (double ce : {0.3, 0.5, 0.7, 0.9, 1.0}) {
      add("restitution", "paper_clearance", {"contact.damping=" + law, "contact.restitution=" + num(ce)});
    }
  }
  for (const char* scene : {"paper_clearance", "planar_clearance"}) {
    for (const char* law : {"none", "ambrosio", "coulomb", "coulomb_stick"}) {
      add("friction", scene, {std::string("friction.law=") + law});
    }
  }
  for (const char* law : {"none", "ambrosio", "coulomb", "coulomb_stick"}) {
    add("friction", "paper_clearance", {"structure.base=fixed", std::string("friction.law=") + law});
  }
  // The adaptive sub-step policy: tolerance x friction law, and the stiff
  // cases the fixed policy gets wrong.
  for (double tol : {1e-6, 1e-8, 1e-10}) {
    for (const char* law : {"ambrosio", "coulomb_stick", "coulomb"}) {
      add("adaptive", "paper_clearance",
          {"sim.substep_policy=adaptive", "sim.substep_tol=" + num(tol), std::string("friction.law=") + law});
    }
  }
  for (const std::vector<std::string>& extra :
       {std::vector<std::string>{"contact.clearance=5e-6"}, {"torque.tau1=100", "torque.tau2=200"},
        {"contact.damping=flores", "contact.restitution=0.3"}}) {
    std::vector<std::string> sets = {"sim.substep_policy=adaptive", "sim.substep_tol=1e-10",
                                     "friction.law=ambrosio", "contact.stiffness_scale=100"};
    sets.insert(sets.end(), extra.begin(), extra.end());
    add("adaptive x stiffness", "paper_clearance", sets);
  }
  // Dissipation only: no torque, moving joints; energy must only fall.
  for (const char* law : {"ambrosio", "coulomb"}) {
    add("dissipation", "paper_clearance",
        {"torque.tau1=0", "torque.tau2=0", "initial.dtheta1=1.0", "initial.dtheta2=-0.5",
         "contact.restitution=0.7", std::string("friction.law=") + law});
  }
  // Conservative: no damping, no friction; energy = torque work exactly.
  add("conservative", "paper_clearance", {"contact.damping=none", "friction.law=none"});
  add("conservative", "planar_clearance", {"contact.damping=none", "friction.law=none"});
  for (double h : {1e-4, 2e-4, 5e-4, 1e-3}) {
    const std::string H = "sim.step=" + num(h), O = "sim.output_interval=" + num(h);
    add("step", "paper_ideal", {H, O});
    add("step", "planar_ideal", {H, O});
    add("step", "paper_clearance", {H, O, "sim.substep=" + num(std::min(h, 2e-5))});
  }
  // Pairs.
  for (double k : {0.01, 100.0}) {
    for (double x : {0.1, 20.0}) {
      add("stiffness x torque", "paper_clearance",
          {"contact.stiffness_scale=" + num(k), "torque.tau1=" + num(5.0 * x), "torque.tau2=" + num(10.0 * x)});
    }
  }
  for (double cl : {5e-6, 5e-3}) {
    for (const char* law : {"none", "coulomb"}) {
      add("clearance x friction", "paper_clearance",
          {"contact.clearance=" + num(cl), std::string("friction.law=") + law});
    }
  }
  for (const char* law : {"none", "ambrosio", "coulomb"}) {
    add("torque x friction", "paper_clearance",
        {"torque.tau1=100", "torque.tau2=200", std::string("friction.law=") + law});
  }
  for (double k : {0.01, 100.0}) {
    for (const char* law : {"lankarani_nikravesh", "flores"}) {
      add("stiffness x restitution", "paper_clearance",
          {"contact.stiffness_scale=" + num(k), std::string("contact.damping=") + law, "contact.restitution=0.3"});
    }
  }
  for (double k : {0.01, 100.0}) {
    for (double cl : {5e-6, 5e-3}) {
      add("stiffness x clearance", "paper_clearance",
          {"contact.stiffness_scale=" + num(k), "contact.clearance=" + num(cl)});
    }
  }
  return c;
}

/// Runs jobs on at most `threads` threads.
void parallel(std::size_t n, int threads, const std::function<void(std::size_t)>& job) {
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    for (std::size_t i; (i = next++) < n;) job(i);
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
}

std::mutex g_print;

void printCase(const Case& c) {
  std::lock_guard<std::mutex> lock(g_print);
  const st::Outcome& o = c.out;
  std::printf("%-15s %-24s %-16s %-62s subst/s %8.3g  P %8.2g L %8.2g  Erise %8.2g  pen %8.2g m  %6.2f s\n",
              st::verdictName(o.verdict), c.group.c_str(), c.scene.c_str(), joined(c.sets).c_str(),
              o.substeps_per_second, o.momentum_rel_linear, o.momentum_rel_angular, o.energy_rise_rel,
              o.max_penetration, o.run.wall_seconds);
  if (!o.reason.empty()) std::printf("    %s\n", o.reason.c_str());
  std::fflush(stdout);
}

/// How a cell walks: the fixed contact sub-step under a 1 ms step, the step
/// itself (sim.step = sim.substep), or the adaptive policy's tolerance.
enum class Walk { Substep, WholeStep, Adaptive };

/// The adaptive policy's tolerances, walked down (Ambrosio friction: plain
/// Coulomb's sign flip defeats error control).
const std::vector<double> kTolerances = {1e-4, 1e-6, 1e-8, 1e-10, 1e-12};

/// A cell of the stiffness x clearance table: a walk down one grid.
struct Cell {
  double stiffness = 1.0, clearance = 5e-4;
  Walk mode = Walk::Substep;
  std::vector<Case> walk;  ///< runs from the largest sub-step down to the first trustworthy
  int stable = -1;         ///< index in walk of the first trustworthy run, or -1
};

void walkCell(Cell& cell, const std::string& scenes, const std::string& dur, const st::Bounds& b) {
  const bool adaptive = cell.mode == Walk::Adaptive;
  for (double h : adaptive ? kTolerances : kSubsteps) {
    if (gimbalsim::io::stopRequested()) return;  // the walk keeps its whole cases
    Case c{cell.mode == Walk::WholeStep ? "step walk" : adaptive ? "adaptive walk" : "substep walk",
           "paper_clearance",
           {"sim.duration=" + dur, "contact.stiffness_scale=" + num(cell.stiffness),
            "contact.clearance=" + num(cell.clearance)},
           {}};
    if (adaptive) {
      c.sets.insert(c.sets.end(), {"sim.substep_policy=adaptive", "friction.law=ambrosio", "sim.substep_tol=" + num(h)});
    } else {
      c.sets.push_back("sim.substep=" + num(h));
    }
    if (cell.mode == Walk::WholeStep) c.sets.push_back("sim.step=" + num(h));
    c.out = st::runCase(scenes + "/" + c.scene + ".yaml", c.sets, b);
    c.ran = true;
    printCase(c);
    cell.walk.push_back(c);
    if (c.out.verdict == st::Verdict::Trustworthy) {
      cell.stable = static_cast<int>(cell.walk.size()) - 1;
      return;
    }
  }
}

char letter(st::Verdict v) {
  switch (v) {
    case st::Verdict::Trustworthy: return 'T';
    case st::Verdict::Stopped: return 'S';
    case st::Verdict::SilentlyWrong: return 'W';
    case st::Verdict::StoppedUnclear: return 'U';
    case st::Verdict::Refused: return 'R';
  }
  return '?';
}

/// The walked value of a run: its sim.substep or sim.substep_tol.
std::string walkedValue(const std::vector<std::string>& sets) {
  for (const char* key : {"sim.substep=", "sim.substep_tol="}) {
    for (const auto& s : sets) {
      if (s.rfind(key, 0) == 0) return s.substr(std::string(key).size());
    }
  }
  return "";
}

/// Effective restitution of one impact per damping law (fixed base, no
/// friction, no torque, fine sub-step).
struct RestitutionRow {
  double ce = 0.0;
  std::map<std::string, double> eff;  ///< damping law -> effective c_e
};

std::vector<RestitutionRow> restitutionTable(const std::string& scenes, double v_in) {
  std::vector<RestitutionRow> rows;
  for (double ce : {0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 1.0}) {
    RestitutionRow r;
    r.ce = ce;
    for (const auto& law : kDamping) {
      const gs::Model m = gs::loadScene(scenes + "/paper_clearance.yaml",
                                        {"structure.base=fixed", "friction.law=none", "torque.tau1=0",
                                         "torque.tau2=0", "sim.substep=1e-6", "sim.event_tol=1e-12",
                                         "contact.damping=" + law, "contact.restitution=" + num(ce)})
                              .model;
      r.eff[law] = st::effectiveRestitution(m, v_in);
    }
    rows.push_back(r);
  }
  return rows;
}

std::string markdown(const std::vector<Cell>& cells, const std::vector<RestitutionRow>& rest, double v_in,
                     const std::string& dur, const st::Bounds& b) {
  std::ostringstream md;
  md << "Generated by `build/bin/gimbalsim_stress --markdown` (paper_clearance scene, "
     << "sim.step = 1 ms, sim.duration = " << dur << " s, torques 5 / 10 N m). "
     << "Trustworthy: finished, no NaN, momentum drift below " << num(b.momentum_rel)
     << " of its scale, the energy balance (kinetic + Hertz - torque work) never rising by more than "
     << num(b.energy_rel) << " of the energy scale, penetration below the clearance.\n\n";
  for (Walk mode : {Walk::Substep, Walk::WholeStep, Walk::Adaptive}) {
    if (mode == Walk::Adaptive) {
      md << "Largest trustworthy `sim.substep_tol` with `sim.substep_policy: adaptive` (Ambrosio friction, "
            "`sim.step` = 1 ms), walking down 1e-4, 1e-6, ... 1e-12, and the RK4 sub-steps it costs per "
            "simulated second; then what each tolerance did:\n\n";
    } else {
      md << (mode == Walk::WholeStep ? "Largest trustworthy step with `sim.step = sim.substep` [s] (every step "
                                       "that small, contact or not)"
                                     : "Largest trustworthy contact sub-step `sim.substep` [s] with `sim.step` = "
                                       "1 ms (fixed policy)")
         << ", walking down 1e-3, 5e-4, 2e-4, ... 1e-6, and the RK4 sub-steps it costs per simulated second; "
            "then what each size did from 1e-3 down (T trustworthy, S stopped with a diagnostic naming the "
            "limit, W silently wrong, U stopped without naming a limit):\n\n";
    }
    md << "| stiffness scale (K [N/m^1.5]) |";
    for (double cl : kClearance) md << " c = " << num(cl) << " m |";
    md << "\n|---|";
    for (std::size_t i = 0; i < kClearance.size(); ++i) md << "---|";
    md << "\n";
    for (double k : kStiffness) {
      md << "| x" << num(k) << " (" << num(8.676e9 * k, 3) << ") |";
      for (double cl : kClearance) {
        const Cell* cell = nullptr;
        for (const auto& c : cells) {
          if (c.stiffness == k && c.clearance == cl && c.mode == mode) cell = &c;
        }
        std::string walk;
        if (cell != nullptr) {
          for (const auto& w : cell->walk) walk += letter(w.out.verdict);
        }
        if (cell == nullptr) {
          md << " - |";
        } else if (cell->stable < 0) {
          md << " none " << walk << " |";
        } else {
          const Case& c = cell->walk[cell->stable];
          md << " **" << walkedValue(c.sets) << "** (" << num(c.out.substeps_per_second, 2) << "/s) " << walk
             << " |";
        }
      }
      md << "\n";
    }
    md << "\n";
  }
  if (!rest.empty()) {
    md << "Effective coefficient of restitution of one impact (fixed base, no friction, journal thrown at "
       << num(v_in) << " m/s, sub-step 1 us) against the requested c_e, and the energy lost per impact "
       << "1 - c_eff^2 (requested 1 - c_e^2):\n\n";
    md << "| c_e | 1 - c_e^2 |";
    for (const auto& law : kDamping) md << " " << law << " c_eff (loss) |";
    md << "\n|---|---|";
    for (std::size_t i = 0; i < kDamping.size(); ++i) md << "---|";
    md << "\n";
    for (const auto& r : rest) {
      md << "| " << num(r.ce) << " | " << num(1 - r.ce * r.ce) << " |";
      for (const auto& law : kDamping) {
        const double e = r.eff.at(law);
        md << " " << num(e) << " (" << num(1 - e * e) << ") |";
      }
      md << "\n";
    }
  }
  return md.str();
}

bool updateReadme(const std::string& path, const std::string& table) {
  std::ifstream in(path);
  if (!in) return false;
  std::stringstream buf;
  buf << in.rdbuf();
  std::string text = buf.str();
  const std::string begin = "<!-- stress-table:begin -->", end = "<!-- stress-table:end -->";
  const auto a = text.find(begin), z = text.find(end);
  if (a == std::string::npos || z == std::string::npos || z < a) return false;
  text = text.substr(0, a + begin.size()) + "\n" + table + text.substr(z);
  try {
    gimbalsim::io::writeFileAtomically(path, text);
  } catch (const gimbalsim::io::OutputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return false;
  }
  return true;
}

/// Throws io::OutputError naming the file.
void writeCsv(const std::string& path, const std::vector<const Case*>& all) {
  if (const auto dir = std::filesystem::path(path).parent_path(); !dir.empty()) std::filesystem::create_directories(dir);
  std::ostringstream f;
  f << "group,scene,sets,verdict,reason,t_end_s,impacts,substeps,substeps_per_s,max_substeps_in_step,"
       "momentum_rel_linear,momentum_rel_angular,energy_rise_rel,energy_change_rel,energy_final_rel,"
       "max_penetration_m,penetration_limit_m,wall_s\n";
  auto q = [](std::string s) {
    for (auto& ch : s) {
      if (ch == '"') ch = '\'';
    }
    return "\"" + s + "\"";
  };
  f.precision(6);
  for (const Case* c : all) {
    const st::Outcome& o = c->out;
    f << q(c->group) << "," << c->scene << "," << q(joined(c->sets)) << "," << st::verdictName(o.verdict) << ","
      << q(o.reason) << "," << o.run.t_end << "," << o.run.stats.impacts << "," << o.run.stats.substeps << ","
      << o.substeps_per_second << "," << o.run.stats.max_substeps_in_step << "," << o.momentum_rel_linear << ","
      << o.momentum_rel_angular << "," << o.energy_rise_rel << "," << o.energy_change_rel << ","
      << o.energy_final_rel << "," << o.max_penetration << "," << o.penetration_limit << ","
      << o.run.wall_seconds << "\n";
  }
  gimbalsim::io::writeFileAtomically(path, f.str());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"gimbalsim_stress: numerical stability stress grid (issue 4)"};
  std::string scenes = GIMBALSIM_SCENES_DIR, csv = "out/stress/stress.csv", readme, dur = "1";
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
  app.add_option("--duration", dur, "simulated time of each run [s]");
  app.add_option("--threads", threads, "runs in parallel (at most 2 on this machine)")->check(CLI::Range(1, 2));
  app.add_option("--momentum-bound", b.momentum_rel, "relative momentum drift bound");
  app.add_option("--energy-bound", b.energy_rel, "relative energy rise bound");
  app.add_flag("--markdown", md, "print the README table");
  app.add_option("--update-readme", readme, "replace the block between the stress-table markers in this file");
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
  CLI11_PARSE(app, argc, argv);
  if (!one_scene.empty()) {
    Case c{"case", one_scene, one_sets, {}};
    const std::string path = one_scene.find('/') == std::string::npos ? scenes + "/" + one_scene + ".yaml" : one_scene;
    c.out = st::runCase(path, one_sets, b);
    printCase(c);
    std::printf("impacts %lld, sub-steps %lld, energy balance change %.3g (final %.3g) of scale\n",
                c.out.run.stats.impacts, c.out.run.stats.substeps, c.out.energy_change_rel, c.out.energy_final_rel);
    return st::acceptable(c.out.verdict) ? 0 : 1;
  }
  if (long_only) no_grid = no_sweeps = long_run = true;
  // SIGINT/SIGTERM: cases running finish, the rest are skipped, the CSV holds the whole cases.
  gimbalsim::io::installStopHandlers();

  const auto t0 = std::chrono::steady_clock::now();
  std::vector<const Case*> all;
  std::vector<Case> sw;
  if (!no_sweeps) {
    sw = sweeps(dur);
    parallel(sw.size(), threads, [&](std::size_t i) {
      if (gimbalsim::io::stopRequested()) return;
      sw[i].out = st::runCase(scenes + "/" + sw[i].scene + ".yaml", sw[i].sets, b);
      sw[i].ran = true;
      printCase(sw[i]);
    });
    for (const auto& c : sw) {
      if (c.ran) all.push_back(&c);
    }
  }
  std::vector<Cell> cells;
  if (!no_grid) {
    for (Walk mode : {Walk::Substep, Walk::WholeStep, Walk::Adaptive}) {
      for (double k : kStiffness) {
        for (double cl : kClearance) cells.push_back({k, cl, mode, {}, -1});
      }
    }
    parallel(cells.size(), threads, [&](std::size_t i) { walkCell(cells[i], scenes, dur, b); });
    for (const auto& cell : cells) {
      for (const auto& c : cell.walk) all.push_back(&c);
    }
  }
  std::vector<Case> longc;
  if (long_run && !gimbalsim::io::stopRequested()) {
    std::vector<std::string> sets = {"sim.duration=3600", "sim.output_interval=0.01"};
    sets.insert(sets.end(), long_sets.begin(), long_sets.end());
    longc.push_back({"long run", long_scene, sets, {}});
    longc[0].out = st::runCase(scenes + "/" + long_scene + ".yaml", sets, b);
    printCase(longc[0]);
    const st::Outcome& o = longc[0].out;
    std::printf("long run: %s, %.1f s simulated in %.1f s wall (%.1f s stepping), %lld impacts, "
                "%.3g sub-steps/s, momentum drift P %.3g L %.3g (relative), energy balance: max rise %.3g, "
                "final change %.3g (relative)\n",
                st::verdictName(o.verdict), o.run.t_end, o.run.wall_seconds, o.run.step_seconds,
                o.run.stats.impacts, o.substeps_per_second, o.momentum_rel_linear, o.momentum_rel_angular,
                o.energy_rise_rel, o.energy_final_rel);
    all.push_back(&longc[0]);
  }
  try {
    if (!csv.empty() && !all.empty()) writeCsv(csv, all);
  } catch (const std::exception& e) {  // io::OutputError, or the directory not creatable
    std::cerr << "error: " << e.what() << "\n";
    return 4;  // an output could not be written (README "Exit codes")
  }
  if (gimbalsim::io::stopRequested()) {
    std::fprintf(stderr, "gimbalsim_stress: interrupted by %s after %zu whole runs (in the CSV); no table written\n",
                 gimbalsim::io::stopSignalName(), all.size());
    return gimbalsim::io::stopExitCode();
  }

  std::vector<RestitutionRow> rest;
  if (!no_sweeps) rest = restitutionTable(scenes, v_in);
  const std::string table = markdown(cells, rest, v_in, dur, b);
  if (md) std::cout << "\n" << table;
  if (!readme.empty() && !updateReadme(readme, table)) {
    std::cerr << "could not update " << readme << " (missing stress-table markers?)\n";
    return 2;
  }

  int failures = 0;
  std::map<std::string, int> count;
  for (const Case* c : all) {
    ++count[st::verdictName(c->out.verdict)];
    if (!st::acceptable(c->out.verdict)) ++failures;
  }
  std::printf("\n%zu runs in %.1f s wall:", all.size(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  for (const auto& [k, n] : count) std::printf(" %s %d", k.c_str(), n);
  std::printf("\n");
  if (failures > 0) {
    std::printf("\n*** %d FAILING RUN(S): finished without a diagnostic but wrong, or stopped unclearly ***\n",
                failures);
    for (const Case* c : all) {
      if (!st::acceptable(c->out.verdict)) {
        std::printf("  %s  %s --set %s\n    %s\n", st::verdictName(c->out.verdict), c->scene.c_str(),
                    joined(c->sets, " --set ").c_str(), c->out.reason.c_str());
      }
    }
    return 1;
  }
  return 0;
}
