// The stress grid's Markdown: see stress_page.hpp.
#include "stress_page.hpp"

#include <cmath>
#include <map>
#include <sstream>

namespace gimbalsim::stress {

char letter(Verdict v) {
  switch (v) {
    case Verdict::Trustworthy: return 'T';
    case Verdict::Stopped: return 'S';
    case Verdict::SilentlyWrong: return 'W';
    case Verdict::StoppedUnclear: return 'U';
    case Verdict::Refused: return 'R';
  }
  return '?';
}

namespace {

/// Runs per group and verdict, the stops by the key that named them, the failures.
void verdicts(std::ostringstream& md, const std::vector<const Case*>& all) {
  std::vector<std::string> groups;
  std::map<std::string, std::map<Verdict, int>> count;
  std::map<Verdict, int> total;
  std::map<std::string, int> stops;
  for (const Case* c : all) {
    if (!count.contains(c->group)) groups.push_back(c->group);
    ++count[c->group][c->out.verdict];
    ++total[c->out.verdict];
    if (c->out.verdict == Verdict::Stopped) {
      const char* key = c->out.run.stop.key;
      ++stops[key != nullptr && *key != '\0' ? key : "NaN/Inf"];
    }
  }
  const int failures = total[Verdict::SilentlyWrong] + total[Verdict::StoppedUnclear] + total[Verdict::Refused];
  md << "**" << all.size() << " runs: " << total[Verdict::Trustworthy] << " TRUSTWORTHY, " << total[Verdict::Stopped]
     << " STOPPED with a diagnostic naming the limit, " << failures
     << " failing** (SILENTLY_WRONG, STOPPED_UNCLEAR or REFUSED; the tool exits 1 when there is one).";
  if (!stops.empty()) {
    md << " The stops by the limit named:";
    const char* sep = " ";
    for (const auto& [key, n] : stops) md << sep << "`" << key << "` " << n, sep = ", ";
    md << ".";
  }
  md << "\n\n| group | runs | TRUSTWORTHY | STOPPED | failing |\n|---|---|---|---|---|\n";
  for (const auto& g : groups) {
    auto& n = count[g];
    md << "| " << g << " | " << (n[Verdict::Trustworthy] + n[Verdict::Stopped] + n[Verdict::SilentlyWrong] +
                                 n[Verdict::StoppedUnclear] + n[Verdict::Refused])
       << " | " << n[Verdict::Trustworthy] << " | " << n[Verdict::Stopped] << " | "
       << n[Verdict::SilentlyWrong] + n[Verdict::StoppedUnclear] + n[Verdict::Refused] << " |\n";
  }
  md << "\n";
  if (failures > 0) {
    md << "Failing runs:\n\n";
    for (const Case* c : all) {
      if (!acceptable(c->out.verdict)) {
        md << "- " << verdictName(c->out.verdict) << ": `" << c->scene << " " << joined(c->sets) << "`: "
           << c->out.reason << "\n";
      }
    }
    md << "\n";
  }
}

void walkTable(std::ostringstream& md, const std::vector<Cell>& cells, Walk mode) {
  if (mode == Walk::Adaptive) {
    md << "### Adaptive policy: largest trustworthy `sim.substep_tol`\n\n"
          "With `sim.substep_policy: adaptive` (Ambrosio friction, `sim.step` = 1 ms), walking down 1e-4, "
          "1e-6, ... 1e-12, and the RK4 sub-steps it costs per simulated second; then what each tolerance did:\n\n";
  } else if (mode == Walk::WholeStep) {
    md << "### Largest trustworthy step with `sim.step = sim.substep` [s]\n\n"
          "Every step that small, contact or not, walking down 1e-3, 5e-4, 2e-4, ... 1e-6, and the RK4 "
          "sub-steps it costs per simulated second; then what each size did from 1e-3 down:\n\n";
  } else {
    md << "### Largest trustworthy contact sub-step `sim.substep` [s]\n\n"
          "With `sim.step` = 1 ms (fixed policy), walking down 1e-3, 5e-4, 2e-4, ... 1e-6, and the RK4 "
          "sub-steps it costs per simulated second; then what each size did from 1e-3 down (T trustworthy, "
          "S stopped with a diagnostic naming the limit, W silently wrong, U stopped without naming a limit):\n\n";
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
        md << " **" << walkedValue(c.sets) << "** (" << num(c.out.substeps_per_second, 2) << "/s) " << walk << " |";
      }
    }
    md << "\n";
  }
  md << "\n";
}

void restitution(std::ostringstream& md, const std::vector<RestitutionRow>& rest, double v_in) {
  md << "### Effective restitution per damping law\n\n"
     << "Effective coefficient of restitution of one impact (fixed base, no friction, journal thrown at " << num(v_in)
     << " m/s, sub-step 1 us) against the requested c_e, and the energy lost per impact "
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
  md << "\n";
}

}  // namespace

std::string pageBody(const PageInput& in) {
  std::ostringstream md;
  const Bounds& b = in.bounds;
  // The opening says what this study ran (pass 55: a long run alone was described as the sweeps and the walk).
  md << "`build/bin/gimbalsim_stress` (tools/stress/): ";
  if (in.sweeps_ran) {
    md << "the paper scenes with one parameter changed at a time and in pairs (contact stiffness, clearance, "
          "torques, restitution per damping law, friction law, step, the adaptive policy's tolerance), every pair "
          "of joint kinds the scenes use (clearance in joint 1, in both, spatial) with each friction law"
       << (in.grid_ran ? ", and " : "");
  }
  if (in.grid_ran) md << "for each contact stiffness and clearance a walk down the sub-step until the run is trustworthy";
  if (in.sweeps_ran || in.grid_ran) {
    md << "; sim.duration = " << in.duration << " s, sim.step = 1 ms (2.5e-4 s in paper_spatial1 and "
       << "paper_both_spatial), torques 5 / 10 N m unless a run changes them.";
  } else {
    md << "the long run alone (no sweep and no sub-step walk ran).";
  }
  md << " The CSV of every run is " << in.csv_path << ".\n\nTRUSTWORTHY: finished, no NaN, momentum drift below " << num(b.momentum_rel)
     << " of its scale, the energy balance (kinetic + Hertz - torque work) never rising by more than "
     << num(b.energy_rel) << " of the energy scale (not an invariant with a spatial joint, so not checked there), "
     << "penetration below the limit. STOPPED: stopped with a "
     << "diagnostic naming the limit it hit (acceptable).\n\n";
  if (!in.all.empty()) verdicts(md, in.all);
  if (in.cells != nullptr && !in.cells->empty()) {
    for (Walk mode : kWalks) walkTable(md, *in.cells, mode);
  }
  if (in.restitution != nullptr && !in.restitution->empty()) restitution(md, *in.restitution, in.v_in);
  if (in.long_run != nullptr) {
    const Outcome& o = in.long_run->out;
    // its length is the --long-set's (pass 55: a 0.1 s run was headed "One simulated hour")
    md << (std::fabs(o.run.t_end - 3600.0) < 1e-6 ? "### One simulated hour" : "### The long run") << "\n\n`" << in.long_run->scene << " " << joined(in.long_run->sets) << "`: **"
       << verdictName(o.verdict) << "**, " << num(o.run.t_end, 4) << " s simulated in " << num(o.run.wall_seconds, 3)
       << " s wall (" << num(o.run.step_seconds, 3) << " s stepping), " << o.run.stats.impacts << " impacts, "
       << num(o.substeps_per_second) << " sub-steps per simulated second, momentum drift P " << num(o.momentum_rel_linear)
       << " L " << num(o.momentum_rel_angular) << " (relative), energy balance: max rise " << num(o.energy_rise_rel)
       << ", final change " << num(o.energy_final_rel) << " (relative; friction and impacts dissipate).\n";
    if (!o.reason.empty()) md << "\n" << o.reason << "\n";
  }
  return md.str();
}

}  // namespace gimbalsim::stress
