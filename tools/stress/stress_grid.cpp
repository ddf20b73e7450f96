// The stress grid's definition: see stress_grid.hpp.
#include "stress_grid.hpp"

#include <algorithm>

#include "gimbalsim/input/value_format.hpp"

namespace gimbalsim::stress {

std::string num(double x, int prec) { return formatSignificant(x, prec); }

std::string joined(const std::vector<std::string>& v, const char* sep) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : sep) + x;
  return s;
}

const std::vector<double> kSubsteps = {1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5, 5e-6, 2e-6, 1e-6};
const std::vector<double> kStiffness = {0.01, 0.1, 1.0, 10.0, 100.0};
const std::vector<double> kClearance = {5e-6, 5e-5, 5e-4, 5e-3};
const std::vector<std::string> kDamping = {"hunt_crossley", "lankarani_nikravesh", "flores"};
const std::vector<double> kTolerances = {1e-4, 1e-6, 1e-8, 1e-10, 1e-12};
const std::vector<double> kRestitutions = {0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.95, 1.0};

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
  // The adaptive sub-step policy: tolerance x friction law (plain coulomb is
  // refused with it), and the stiff cases the fixed policy gets wrong.
  for (double tol : {1e-6, 1e-8, 1e-10}) {
    for (const char* law : {"ambrosio", "coulomb_stick"}) {
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
  // Every pair of joint kinds the shipped scenes use, with each friction law
  // that acts on a spatial joint (coulomb_stick is a planar joint 2's only).
  // The grid's momentum bound is the run's own: paper_spatial1 and
  // paper_both_spatial ship with a looser sim.momentum_tol (a spatial joint
  // 1 drifts by 1e-9 of the still tiny momenta of the first milliseconds).
  for (const char* scene : {"paper_planar1", "paper_both_planar", "paper_spatial2", "paper_spatial1",
                            "paper_both_spatial", "planar_spatial2"}) {
    for (const char* law : {"none", "ambrosio", "coulomb"}) {
      add("joint kinds", scene, {"sim.momentum_tol=1e-9", std::string("friction.law=") + law});
    }
    add("joint kinds", scene, {"sim.momentum_tol=1e-9", "torque.tau1=50", "torque.tau2=100"});
  }
  add("conservative", "paper_both_planar", {"contact.damping=none", "friction.law=none"});
  add("conservative", "paper_planar1", {"contact.damping=none", "friction.law=none"});
  for (double k : {0.01, 100.0}) {
    add("joint kinds x stiffness", "paper_spatial2", {"contact.stiffness_scale=" + num(k)});
    add("joint kinds x stiffness", "paper_both_planar", {"contact.stiffness_scale=" + num(k)});
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

std::vector<Cell> gridCells() {
  std::vector<Cell> cells;
  for (Walk mode : kWalks) {
    for (double k : kStiffness) {
      for (double cl : kClearance) cells.push_back({k, cl, mode, {}, -1});
    }
  }
  return cells;
}

const std::vector<double>& walkValues(Walk mode) { return mode == Walk::Adaptive ? kTolerances : kSubsteps; }

Case walkCase(const Cell& cell, double h, const std::string& dur) {
  const bool adaptive = cell.mode == Walk::Adaptive;
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
  return c;
}

std::string walkedValue(const std::vector<std::string>& sets) {
  for (const char* key : {"sim.substep=", "sim.substep_tol="}) {
    for (const auto& s : sets) {
      if (s.rfind(key, 0) == 0) return s.substr(std::string(key).size());
    }
  }
  return "";
}

std::vector<std::pair<std::string, std::string>> longSets(const std::vector<std::string>& long_sets) {
  // The hour's own keys unless --long-set gives them, then the user's, each key once (its last --long-set acts):
  // a key listed twice (3600 and the user's 60) would say both on the page and in the CSV (pass 49, pass 50).
  const auto keyOf = [](const std::string& set) { return set.substr(0, set.find('=')); };
  const auto givenAfter = [&](std::size_t from, const std::string& set) {
    return std::any_of(long_sets.begin() + static_cast<std::ptrdiff_t>(from), long_sets.end(),
                       [&](const std::string& s) { return keyOf(s) == keyOf(set); });
  };
  std::vector<std::pair<std::string, std::string>> out;
  for (const char* own : {"sim.duration=3600", "sim.output_interval=0.01"}) {
    if (!givenAfter(0, own)) out.emplace_back(own, std::string("the long run's own '") + own + "'");
  }
  for (std::size_t i = 0; i < long_sets.size(); ++i) {
    if (!givenAfter(i + 1, long_sets[i])) {
      out.emplace_back(long_sets[i], "--long-set #" + std::to_string(i + 1) + " '" + long_sets[i] + "'");
    }
  }
  return out;
}

Case longCase(const std::string& scene, const std::vector<std::string>& long_sets) {
  std::vector<std::string> sets;
  for (const auto& [set, label] : longSets(long_sets)) sets.push_back(set);
  return {"long run", scene, sets, {}};
}

std::vector<std::string> restitutionSets(const std::string& law, double ce) {
  return {"structure.base=fixed", "friction.law=none", "torque.tau1=0", "torque.tau2=0", "sim.substep=1e-6",
          "sim.event_tol=1e-12", "contact.damping=" + law, "contact.restitution=" + num(ce)};
}

}  // namespace gimbalsim::stress
