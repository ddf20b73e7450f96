// The worst-case work of a step (docs/MODEL.md 7.5, 7.8): the switch locator
// needs at most locateIterations() trials whatever the switch function does,
// and no work unit of a step takes more derivative evaluations than
// derivativesPerUnit() says, so firmware_sim's bound (units x derivatives x
// time per derivative) is an upper bound of the work, not an estimate.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "gimbalsim/dynamics/integrator.hpp"
#include "gimbalsim/dynamics/simulate.hpp"
#include "test_util.hpp"

namespace gimbalsim {
namespace {

/// A switch at a chosen time t_root after the sub-step's start, with a
/// signed value shaped to slow regula falsi down (or a bare predicate).
struct TimeSwitch {
  double t0 = 0.0, t_root = 0.0;
  bool is_signed = true;
  std::function<double(double)> g;  ///< of the time past the root [s]
  bool signedValue() const { return is_signed; }
  double value(const State<FixedIdeal>& x) const { return g(x.t - t0 - t_root); }
  bool past(const State<FixedIdeal>& x, double /*g*/) const { return x.t - t0 > t_root; }
};

struct Located {
  StepStatus status;
  long long trials;
  double t_past;  ///< time of the state handed back, from the sub-step's start [s]
};

Located locate(const Model& m, const TimeSwitch& sw_in, double dt, double guess) {
  Data<FixedIdeal> d(m);
  State<FixedIdeal> s = initialState<FixedIdeal>(InitialParams{});
  const Input u{Vec2(1.0, 0.5)};
  evalDerivative(m, d, s, u, d.k[0]);
  rk4(m, d, s, u, dt, d.trial, true);
  TimeSwitch sw = sw_in;
  sw.t0 = s.t;
  SubstepBudget budget{0, 1000};
  const StepResult r = locateSwitch(m, d, s, u, dt, sw, budget, guess);
  return {r.status, d.stats.event_iterations, s.t - sw.t0};
}

TEST(WorkBound, LocatorNeverExceedsItsIterationBoundOnHostileSwitchFunctions) {
  Model m = test::scene("paper_ideal", {"structure.base=fixed"}).model;
  const double dt = 2e-5;
  m.integrator.event_tol = 1e-9;
  const int bound = locateIterations(m.integrator, dt);
  ASSERT_EQ(bound, 17);  // ceil(log2(2e4)) + 2
  // Shapes that defeat regula falsi: a high-multiplicity root, a step, a
  // value tiny on one side and huge on the other, a slope that flips.
  const std::vector<std::pair<const char*, std::function<double(double)>>> shapes = {
      {"ninth power", [](double x) { return std::pow(x * 1e5, 9.0); }},
      {"step", [](double x) { return x > 0.0 ? 1.0 : -1.0; }},
      {"lopsided", [](double x) { return x > 0.0 ? 1e12 * x : 1e-6 * x; }},
      {"lopsided reversed", [](double x) { return x > 0.0 ? 1e-6 * x : 1e12 * x; }},
      {"sqrt", [](double x) { return std::copysign(std::sqrt(std::fabs(x)), x); }},
      {"cube root", [](double x) { return std::cbrt(x); }},
  };
  int worst = 0;
  for (const auto& [name, g] : shapes) {
    for (double frac : {1e-7, 0.013, 0.31, 0.5, 0.77, 0.999, 1.0 - 1e-7}) {
      for (double guess : {-1.0, 0.5 * dt, 0.999 * dt, frac * dt}) {
        for (bool is_signed : {true, false}) {
          const Located r = locate(m, TimeSwitch{0.0, frac * dt, is_signed, g}, dt, guess);
          ASSERT_EQ(r.status, StepStatus::Ok) << name << " root at " << frac << " dt";
          EXPECT_LE(r.trials, bound) << name << " root at " << frac << " dt, guess " << guess;
          // the state handed back is past the switch, by at most event_tol (and round-off)
          EXPECT_GT(r.t_past, frac * dt) << name;
          EXPECT_LE(r.t_past - frac * dt, m.integrator.event_tol * (1.0 + 1e-6)) << name << " root at " << frac;
          worst = std::max(worst, static_cast<int>(r.trials));
        }
      }
    }
  }
  std::printf("worst trials %d of the bound %d\n", worst, bound);
}

/// Steps a scene for `seconds` and checks every step's derivative
/// evaluations against derivativesPerUnit x its work units; returns the
/// highest ratio seen (evaluations per unit) and the most units in a step.
template <class V>
void checkDerivativesPerUnit(const Scene& sc, double seconds, const std::string& what) {
  const Model& m = sc.model;
  Data<V> d(m);
  auto s = initialState<V>(sc.run.initial);
  const int per_unit = derivativesPerUnit<V>(m);
  const int cap = substepCap(m);
  double worst_ratio = 0.0;
  long long switches = 0;
  const long long steps = std::llround(seconds / m.integrator.step);
  for (long long k = 0; k < steps; ++k) {
    const RunStats before = d.stats;
    ASSERT_EQ(step(m, d, s, Input{sc.run.torque}).status, StepStatus::Ok) << what << " at step " << k;
    const long long evals = d.stats.derivatives - before.derivatives;
    const long long units = (d.stats.substeps - before.substeps) + (d.stats.mode_entries - before.mode_entries);
    switches += d.stats.mode_entries - before.mode_entries;
    ASSERT_LE(units, cap) << what << " at step " << k;
    ASSERT_LE(evals, per_unit * units) << what << " at step " << k << ": " << evals << " evaluations in " << units
                                       << " units";
    worst_ratio = std::max(worst_ratio, static_cast<double>(evals) / static_cast<double>(units));
  }
  EXPECT_GT(switches, 0) << what << ": no switch was located, so the mode entries went untested";
  std::printf("%-48s %d derivatives per unit allowed, worst step %.2f; cap %d units, worst step %d; %lld switches\n",
              what.c_str(), per_unit, worst_ratio, cap, d.stats.max_substeps_in_step, switches);
}

void checkScene(const std::string& name, const std::vector<std::string>& sets, double seconds) {
  const Scene sc = test::scene(name, sets);
  std::string what = name;
  for (const auto& x : sets) what += " " + x;
  dispatchVariant(sc.model, [&](auto tag) { checkDerivativesPerUnit<decltype(tag)>(sc, seconds, what); });
}

TEST(WorkBound, EveryStepStaysWithinItsDerivativeBound) {
  checkScene("paper_clearance", {}, 1.0);
  checkScene("paper_clearance", {"contact.stiffness_scale=100"}, 0.5);
  checkScene("paper_clearance", {"sim.substep_policy=adaptive", "friction.law=ambrosio"}, 0.5);
  checkScene("stickslip_clearance", {"friction.law=coulomb_stick"}, 0.5);
  checkScene("stickslip_clearance", {"friction.law=coulomb_stick", "sim.substep_policy=adaptive"}, 0.5);
  checkScene("paper_spatial2", {}, 0.5);
  checkScene("paper_both_spatial", {}, 0.5);
  checkScene("paper_both_spatial", {"sim.substep_policy=adaptive", "friction.law=ambrosio"}, 0.3);
}

}  // namespace
}  // namespace gimbalsim
