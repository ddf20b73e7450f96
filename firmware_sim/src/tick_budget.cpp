#include "tick_budget.hpp"

#include <algorithm>
#include <cstdio>

#include "gimbalsim/dynamics/forward_dynamics.hpp"
#include "gimbalsim/dynamics/integrator.hpp"
#include "gimbalsim/dynamics/simulate.hpp"
#include "realtime.hpp"

namespace gimbalsim::firmware {
namespace {

/// Median over 7 batches of the time per evaluation [us] (the median shrugs off a descheduled batch).
template <class V>
double timeDerivative(const Model& m, const State<V>& s) {
  Data<V> d(m);
  Input u;
  u.tau = Vec2(1.0, 1.0);
  constexpr int kBatch = 200, kBatches = 7;
  double per[kBatches];
  for (int b = 0; b < kBatches; ++b) {
    const std::int64_t t0 = nowNs();
    for (int i = 0; i < kBatch; ++i) forwardDynamics(m, d, s, u);
    per[b] = static_cast<double>(nowNs() - t0) * 1e-3 / kBatch;
  }
  std::sort(per, per + kBatches);
  return per[kBatches / 2];
}

template <class V>
double derivativeCost(const Model& m, const RunSpec& run) {
  State<V> s = initialState<V>(run.initial);
  double cost = timeDerivative(m, s);
  if constexpr (V::kContact) {
    // Pressed into the bearing along u1 and sliding, so the contact and friction laws run too.
    constexpr int QJ = State<V>::QJ, NB = V::NB;
    for (int j = 0; j < 2; ++j) {
      if (V::kind(j) == ClearanceKind::Ideal) continue;
      s.q(QJ + V::group(j)) = 1.001 * m.contactOf(j).clearance;
      s.q(QJ + V::group(j) + 1) = 0.0;
      s.v(NB + V::group(j) + 1) = 1e-3;
    }
    s.in_contact.fill(true);
    s.v0.fill(1e-3);
    cost = std::max(cost, timeDerivative(m, s));
  }
  return cost;
}

}  // namespace

TickBudget measureTickBudget(const Scene& sc, const Config& c) {
  const Model& m = sc.model;
  TickBudget b;
  b.derivative_us = dispatchVariant(m, [&](auto tag) { return derivativeCost<decltype(tag)>(m, sc.run); });
  b.steps_per_tick = std::max(1, checkConfig(sc, c).steps_per_tick);
  b.substep_cap = m.hasClearance() ? substepCap(m) : 1;  // without clearance a step is one RK4 step
  b.evals_per_substep = dispatchVariant(m, [&](auto tag) { return derivativesPerUnit<decltype(tag)>(m); });
  b.worst_tick_us = (static_cast<double>(b.steps_per_tick) * b.substep_cap * b.evals_per_substep + 1.0) * b.derivative_us;
  b.period_us = c.control_period * 1e6;
  return b;
}

std::string describeTickBudget(const TickBudget& b) {
  char line[320];
  std::snprintf(line, sizeof line,
                "worst-case tick %.0f us = (%d steps x %d work units (cap) x %d derivatives + 1) x %.2f us per "
                "derivative (measured now); period %.0f us",
                b.worst_tick_us, b.steps_per_tick, b.substep_cap, b.evals_per_substep, b.derivative_us, b.period_us);
  return line;
}

std::string tickBudgetWarning(const TickBudget& b) {
  if (!b.exceeds()) return "";
  char line[480];
  std::snprintf(line, sizeof line,
                "warning: the worst-case tick (%.0f us) exceeds the control period (%.0f us): %s",
                b.worst_tick_us, b.period_us,
                b.substep_cap > 1 ? "a tick that uses the whole sub-step cap overruns; raise sim.substep, lower "
                                    "sim.max_substeps, or lengthen the period (--rate, a whole multiple of sim.step)"
                                  : "every tick overruns; lengthen sim.step (fewer RK4 steps per tick) or the "
                                    "period (--rate)");
  return line;
}

}  // namespace gimbalsim::firmware
