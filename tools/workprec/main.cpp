// gimbalsim_workprec: work-precision sweep. For each scene, each contact
// sub-stepping policy (tools/workprec/policies.yaml) and each outer step h:
// the median thread CPU time per simulated second of the RK4 run, and its
// errors against the Dormand-Prince reference at every output row. Writes
// out/workprec/workprec.csv and prints the cheapest setting per target
// boresight accuracy. Plot: /usr/bin/python3 tools/workprec/plot_workprec.py.
//
//   build/bin/gimbalsim_workprec                 # full sweep (minutes)
//   build/bin/gimbalsim_workprec --quick         # a few points (seconds)

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include "gimbalsim/input/key_registry.hpp"
#include "gimbalsim/input/value_format.hpp"
#include "gimbalsim/io/output_file.hpp"
#include "gimbalsim/program/program.hpp"
#include "gimbalsim/scene/scene.hpp"
#include "args.hpp"
#include "points.hpp"
#include "policies.hpp"
#include "workprec.hpp"
#ifdef GIMBALSIM_HAVE_MUJOCO
#include "mujoco_peer.hpp"
#endif


namespace {

using namespace gimbalsim;
using namespace gimbalsim::workprec;

/// Overrides a scene always gets here, and why (printed).
struct SceneDefaults {
  std::vector<std::string> sets;
  const char* why;
};
/// Why a clearance in joint 1 or a spatial joint runs with the smooth law.
constexpr const char* kSmoothLaw =
    "plain Coulomb's sign flip stops the adaptive reference and coulomb_stick is a planar joint 2's alone; the "
    "smooth Ambrosio law is used for the reference and the runs";
const std::map<std::string, SceneDefaults> kSceneDefaults = {
    {"paper_clearance",
     {{"friction.law=coulomb_stick"},
      "plain Coulomb's sign flip stops the adaptive reference; the set-valued Coulomb law with located "
      "stick/slip (coulomb_stick) is used for the reference and the runs"}},
    {"paper_both_planar", {{"friction.law=ambrosio"}, kSmoothLaw}},
    {"paper_planar1", {{"friction.law=ambrosio"}, kSmoothLaw}},
    {"paper_spatial2", {{"friction.law=ambrosio"}, kSmoothLaw}},
    {"paper_spatial1", {{"friction.law=ambrosio"}, kSmoothLaw}},
    {"planar_spatial2", {{"friction.law=ambrosio"}, kSmoothLaw}},
};

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string join(const std::vector<std::string>& v, const char* sep) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : sep) + x;
  return s;
}

void printPoint(const Point& p) {
  if (!p.ok) {
    std::printf("  %-22s h=%-8g %s=%-8s  -- %s\n", p.policy.c_str(), p.h,
                p.sweep_key.empty() ? "sub" : p.sweep_key.c_str(), p.sweep_value.c_str(), p.note.c_str());
    return;
  }
  std::printf("  %-22s h=%-8g sub=%-8g %s  cpu %9.3g s/s  bore max %8.2e end %8.2e  th2 %8.2e  "
              "peakF %8.2e  drift %8.2e  substeps %lld\n",
              p.policy.c_str(), p.h, p.substep,
              p.sweep_key.empty() ? "" : (p.sweep_key + "=" + p.sweep_value).c_str(), p.cpu_per_sim_s,
              p.bore_err_max, p.bore_err_end, p.theta2_err_max, p.peak_force_err_rel, p.momentum_drift_rel,
              p.substeps);
  std::fflush(stdout);
}

/// The overrides every run of a scene gets: its defaults, the guards off,
/// the user's --set, the duration and the row spacing.
std::vector<std::string> baseSets(const Args& a, const std::string& scene) {
  std::vector<std::string> sets;
  if (auto it = kSceneDefaults.find(scene); it != kSceneDefaults.end()) {
    sets = it->second.sets;
    std::printf("\n[%s] with %s: %s\n", scene.c_str(), join(sets, " ").c_str(), it->second.why);
  }
  // The run-time guards (invariants, impact resolution) stop runs that are
  // not accurate enough; here every setting's error is measured against
  // the reference instead, so they are off (a --set can turn them on).
  for (const char* off : {"sim.momentum_tol=0", "sim.energy_tol=0", "sim.min_substeps_per_impact=0"}) {
    sets.push_back(off);
  }
  sets.insert(sets.end(), a.extra_sets.begin(), a.extra_sets.end());
  if (a.duration > 0.0) sets.push_back("sim.duration=" + formatNumber(a.duration));
  sets.push_back("sim.output_interval=" + formatNumber(a.output_interval));
  return sets;
}

/// A refusal of the base scene, each override named as the user gave it: a
/// flag, or the user's own --set #k (not its place in base_sets).
int refuseScene(const Args& a, const std::string& scene, const std::vector<std::string>& base_sets,
                const InputError& e) {
  std::vector<std::string> labels;
  const std::size_t own = base_sets.size() - a.extra_sets.size() - (a.duration > 0.0 ? 2 : 1);
  for (std::size_t i = 0; i < base_sets.size(); ++i) {
    const std::string& s = base_sets[i];
    if (i < own) {
      labels.push_back("gimbalsim_workprec's own setting '" + s + "' of scene " + scene);
    } else if (i < own + a.extra_sets.size()) {
      labels.push_back("--set #" + std::to_string(i - own + 1) + " '" + s + "'");
    } else {
      labels.push_back(s.rfind("sim.duration=", 0) == 0 ? "--duration" : "--output-interval");
    }
  }
  std::cerr << "scene " << scene << " refused:\n";
  for (const std::string& p : relabelledProblems(e, labels)) std::cerr << "error: " << p << "\n";
  return program::refuse("gimbalsim_workprec", "scene " + scene + " refused");
}

/// What the reference says about the scene (printed before its curves).
void printReference(const Scene& base, const Reference& ref, const std::string& out_dir) {
  if (ref.from_cache) {
    std::printf("cached (%s)\n", out_dir.c_str());
  } else {
    std::printf("%.2f s CPU\n", ref.cpu_seconds);
  }
  if (base.model.hasClearance()) {
    std::printf("  reference peak contact force %.6g N (sampled every %g s); that pass and the row pass "
                "(stops every %g s) agree in boresight to %.2e rad at the rows\n",
                ref.rows.peak_contact, ref.peak_dt, base.run.output_interval, ref.self_consistency);
  }
  const StickSlip& ss = ref.stick;
  if (ss.contact_time > 0.0) {
    std::printf("  stick-slip (reference, every %g s): in contact %.3f s; |v_t| < v_a %.3f s, "
                "v_a..v_b (Ambrosio: friction below mu F_n) %.3f s, >= v_b (full friction) %.3f s; "
                "%lld entries below v_b, %lld reversals of v_t\n",
                ss.dt, ss.contact_time, ss.below_va, ss.band, ss.slip, ss.stick_entries, ss.vt_sign_changes);
  }
}

/// One policy's curve on one scene: each point's error and median CPU.
void measureCurve(const Args& a, const std::string& scene, const std::string& path, const Scene& base,
                  const std::vector<std::string>& base_sets, const Reference& ref, const Policy& pol,
                  std::vector<Point>& points) {
  std::vector<std::pair<double, std::string>> sweep;  // (h, sweep value)
  if (pol.sweep_key.empty()) {
    for (double h : a.steps) sweep.emplace_back(h, "");
  } else {
    double h = base.model.integrator.step;
    for (const std::string& s : pol.sets) {
      if (s.rfind("sim.step=", 0) == 0) h = std::stod(s.substr(9));
    }
    for (const std::string& v : pol.sweep_values) sweep.emplace_back(h, v);
  }
  double last_cpu = 0.0;  // [s] per run at the previous point of this curve
  for (const auto& [h, value] : sweep) {
    if (gimbalsim::io::stopRequested()) return;
    if (last_cpu > a.max_run_seconds) {
      std::printf("  %-22s rest of the curve skipped: the last point took %.1f s per run (--max-run-seconds)\n",
                  pol.name.c_str(), last_cpu);
      return;
    }
    Point p;
    p.scene = scene;
    p.policy = pol.name;
    p.h = h;
    p.sweep_key = pol.sweep_key;
    p.sweep_value = value;
    std::vector<std::string> sets = base_sets;
    sets.push_back("sim.step=" + formatNumber(h));
    for (const std::string& s : pol.sets) sets.push_back(expandSet(s, h));
    if (!value.empty()) sets.push_back(pol.sweep_key + "=" + value);
    Scene sc;
    try {
      sc = loadScene(path, sets);
    } catch (const InputError& e) {
      p.note = "refused: " + join(e.problems(), "; ");
      points.push_back(p);
      printPoint(p);
      continue;
    }
    const Model& m = sc.model;
    p.h = m.integrator.step;
    p.substep = m.integrator.substep;
    p.event_tol = m.integrator.event_tol;
    p.ok = compare(runRk4(sc), ref.rows, p);
    if (p.ok) {
      std::vector<double> cpu;
      for (int r = 0; r < a.repeats && p.ok; ++r) {
        cpu.push_back(cpuSecondsOfRun(sc));
        if (cpu.back() < 0.0) p.ok = false, p.note = "timed run stopped";
      }
      p.repeats = a.repeats;
      if (p.ok) p.cpu_per_sim_s = median(cpu) / sc.run.duration;
      if (p.ok) last_cpu = median(cpu);
    }
    if (gimbalsim::io::stopRequested()) return;  // this point's runs were cut short
    if (!p.ok) {  // a point that did not run to its end has no figure: its partial maxima are not one
      p.bore_err_max = p.bore_err_end = p.theta1_err_max = p.theta2_err_max = kNoValue;
      p.peak_force_err_rel = p.momentum_drift_rel = p.cpu_per_sim_s = kNoValue;
    }
    points.push_back(p);
    printPoint(p);
  }
}

/// What went wrong without stopping the sweep; each decides the exit code at the end.
struct Troubles {
  std::vector<std::string> skipped;    ///< scenes whose reference run failed (exit 3)
  std::vector<std::string> uncached;   ///< references that could not be cached (exit 4)
};

/// Every scene of --scenes loaded and checked before any runs: a refused one
/// costs nothing (no point measured, no reference cached). nullopt: all taken.
std::optional<int> loadScenes(const Args& a, std::vector<Scene>& scenes) {
  for (const std::string& scene : a.scenes) {
    const std::vector<std::string> base_sets = baseSets(a, scene);
    try {
      scenes.push_back(loadScene(scenePath(a, scene), base_sets));
    } catch (const InputError& e) {
      return refuseScene(a, scene, base_sets, e);
    }
    if (!(scenes.back().run.duration / a.peak_dt <= 1e10)) {
      return program::refuse("gimbalsim_workprec",
                             "scene " + scene + ": sim.duration / --peak-dt is more than 1e10 reference samples");
    }
    // A point is --repeats runs of sim.duration / h steps each: 1e9 of them ran for hours (pass 68).
    for (const double h : a.steps) {
      if (!(scenes.back().run.duration / h <= 1e8)) {
        return program::refuse("gimbalsim_workprec", "--steps " + formatNumber(h) + ": scene " + scene +
                                                         "'s sim.duration / h is more than 1e8 steps per run");
      }
    }
  }
  return std::nullopt;
}

/// Run: every curve of one scene (loaded by loadScenes).
void measureScene(const Args& a, const std::string& scene, const Scene& base, std::vector<Point>& points,
                  Troubles& troubles) {
  const std::string path = scenePath(a, scene);
  const std::vector<std::string> base_sets = baseSets(a, scene);
  std::printf("\n[%s] %g s, %s, reference: ", scene.c_str(), base.run.duration,
              base.model.floating_base ? "floating base" : "fixed base");
  std::fflush(stdout);
  Reference ref;
  try {
    ref = reference(base, readFile(path) + "\n" + join(base_sets, "\n"), a.out_dir, a.peak_dt);
  } catch (const std::exception& e) {
    std::printf("FAILED (%s); scene skipped\n", e.what());
    troubles.skipped.push_back(scene + " (" + e.what() + ")");
    return;
  }
  if (!ref.cache_unused.empty()) {
    std::fprintf(stderr, "gimbalsim_workprec: reference cache %s: computed again\n", ref.cache_unused.c_str());
  }
  if (!ref.cache_unwritten.empty()) {
    std::fprintf(stderr, "gimbalsim_workprec: error: reference not cached: %s\n", ref.cache_unwritten.c_str());
    troubles.uncached.push_back(ref.cache_unwritten);
  }
  printReference(base, ref, a.out_dir);
  for (const Policy& pol : a.policies) {
    if (pol.contact_only && !base.model.hasClearance()) continue;
    measureCurve(a, scene, path, base, base_sets, ref, pol, points);
  }
#ifdef GIMBALSIM_HAVE_MUJOCO
  if (!a.no_mujoco && !base.model.hasClearance()) {
    for (Point& p : mujocoPoints(base, ref.rows, a.steps, a.repeats)) {
      p.scene = scene;
      points.push_back(p);
      printPoint(p);
    }
  }
#endif
}

/// Report: the cheapest setting per target accuracy and scene.
void printCheapest(const std::vector<Point>& points) {
  std::printf("\nCheapest setting per target max boresight error (median CPU; ms per simulated 5 s in brackets):\n");
  std::printf("%-22s %-9s %-24s %-10s %-10s %-12s %-16s %s\n", "scene", "target", "policy", "h [s]",
              "substep", "sweep", "CPU s per sim s", "bore err max");
  std::vector<std::string> seen;
  for (const Point& p : points) {
    if (std::find(seen.begin(), seen.end(), p.scene) != seen.end()) continue;
    seen.push_back(p.scene);
    for (double target : {1e-3, 1e-6, 1e-9}) {
      const Point* b = cheapestFor(points, p.scene, target);
      if (!b) {
        std::printf("%-22s %-9.0e not reached\n", p.scene.c_str(), target);
        continue;
      }
      std::printf("%-22s %-9.0e %-24s %-10g %-10g %-12s %-8.3g (%6.1f ms) %.2e\n", p.scene.c_str(), target,
                  b->policy.c_str(), b->h, b->substep, b->sweep_value.c_str(), b->cpu_per_sim_s,
                  5e3 * b->cpu_per_sim_s, b->bore_err_max);
    }
  }
}

int mainImpl(int argc, char** argv) {
  Args a;
  if (const auto rc = parseArgs(argc, argv, a)) return *rc;
  std::printf("work-precision sweep: CPU = thread CPU time (CLOCK_THREAD_CPUTIME_ID) of the stepping only, "
              "median of %d runs; errors at every %g s row against Boost.Odeint dopri5 at 1e-12.\n"
              "Timings on a shared machine are noisy.\n",
              a.repeats, a.output_interval);
  // The CSV's temporary exists before the first point: a folder that takes no file costs no run.
  const std::string csv = a.out_dir + "/workprec.csv";
  std::optional<gimbalsim::io::OutputFile> csv_file;
  try {
    csv_file.emplace(csv);
  } catch (const gimbalsim::io::OutputError& e) {
    return program::unwritable("gimbalsim_workprec", e.what());
  }
  std::vector<Scene> scenes;
  if (const auto rc = loadScenes(a, scenes)) return *rc;
  std::vector<Point> points;
  Troubles troubles;
  // SIGINT/SIGTERM: the point being measured is dropped, the CSV holds every whole point before it.
  gimbalsim::io::installStopHandlers();
  for (std::size_t i = 0; i < a.scenes.size(); ++i) {
    if (gimbalsim::io::stopRequested()) break;
    measureScene(a, a.scenes[i], scenes[i], points, troubles);
  }
  markPareto(points);
  if (!csv_file->write(csvText(points)) || !csv_file->commit()) {
    std::fprintf(stderr, "gimbalsim_workprec: error: %s\n", csv_file->error().c_str());
    return program::kOutput;
  }
  std::printf("\nwrote %s (%zu points)\n", csv.c_str(), points.size());
  if (gimbalsim::io::stopRequested()) {
    std::fprintf(stderr, "gimbalsim_workprec: interrupted by %s; the CSV holds the %zu whole points before it\n",
                 gimbalsim::io::stopSignalName(), points.size());
    return gimbalsim::io::stopExitCode();
  }
  printCheapest(points);
  // Every other point was measured and written; the exit code still says what is missing.
  if (!troubles.skipped.empty()) {
    std::fprintf(stderr, "gimbalsim_workprec: error: %zu scene(s) without a reference, not measured (first: %s)\n",
                 troubles.skipped.size(), troubles.skipped.front().c_str());
    return program::kStopped;
  }
  if (!troubles.uncached.empty()) {
    std::fprintf(stderr, "gimbalsim_workprec: error: %zu reference cache(s) not written (first: %s)\n",
                 troubles.uncached.size(), troubles.uncached.front().c_str());
    return program::kOutput;
  }
  return program::kOk;
}

}  // namespace

int main(int argc, char** argv) {
  return gimbalsim::program::guardedMain("gimbalsim_workprec", [&] { return mainImpl(argc, argv); });
}
