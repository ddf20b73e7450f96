#include "tick_budget.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "gimbalsim/dynamics/forward_dynamics.hpp"
#include "gimbalsim/dynamics/integrator.hpp"
#include "gimbalsim/dynamics/simulate.hpp"
#include "realtime.hpp"

namespace gimbalsim::firmware {
namespace {

/// Median over 7 batches of the time per call of f [us] (the median shrugs
/// off a descheduled batch); before() runs ahead of each batch, untimed.
template <class F, class Before>
double medianUs(F&& f, int batch, Before&& before) {
  constexpr int kBatches = 7;
  double per[kBatches];
  for (double& t : per) {
    before();
    const std::int64_t t0 = nowNs();
    for (int i = 0; i < batch; ++i) f();
    t = static_cast<double>(nowNs() - t0) * 1e-3 / batch;
  }
  std::sort(per, per + kBatches);
  return per[kBatches / 2];
}
template <class F>
double medianUs(F&& f) {
  return medianUs(f, 200, [] {});
}

/// Evicts this CPU's caches and TLB as a tick finds them after the loop
/// thread slept while others ran there: a read-modify-write of every cache
/// line of twice the L2 size (the shared L3, 480 MB on some hosts, is not
/// evicted).
class CacheEvictor {
 public:
  CacheEvictor() {
    const long l2 = ::sysconf(_SC_LEVEL2_CACHE_SIZE);
    buf_.assign(2 * static_cast<std::size_t>(l2 > 0 ? l2 : 4L << 20), 0);
  }
  void evict() {
    volatile unsigned char* p = buf_.data();  // volatile: the stores cannot be dropped
    for (std::size_t i = 0; i < buf_.size(); i += 64) p[i] = static_cast<unsigned char>(p[i] + 1);
  }

 private:
  std::vector<unsigned char> buf_;
};

struct UnitCosts {
  double derivative_us = 0.0;  ///< one forwardDynamics, the slower of free and pressed
  double unit_us = 0.0;        ///< one work unit: a whole step in free flight, or an RK4 sub-step pressed
  double cold_us = 0.0;        ///< what a unit costs more when it starts with cold caches (once per tick)
};

/// Times, at the initial state and (with clearance) pressed into the bearing
/// and sliding so that the contact and friction laws run too: a derivative,
/// a whole step in free flight (one RK4 sub-step with the step's own
/// checks), and an RK4 sub-step in contact.
template <class V>
UnitCosts unitCosts(const Model& m, const RunSpec& run) {
  Data<V> d(m);
  Input u;
  u.tau = Vec2(1.0, 1.0);
  const State<V> s0 = initialState<V>(run.initial);
  State<V> x = s0;
  UnitCosts c;
  c.derivative_us = medianUs([&] { forwardDynamics(m, d, s0, u); });
  const auto free_step = [&] {
    x = s0;
    step(m, d, x, u);
  };
  CacheEvictor cache;
  const auto evict = [&] { cache.evict(); };
  c.unit_us = medianUs(free_step);
  c.cold_us = medianUs(free_step, 1, evict) - c.unit_us;
  if constexpr (V::kContact) {
    State<V> pressed = s0;
    constexpr int QJ = State<V>::QJ, NB = V::NB;
    for (int j = 0; j < 2; ++j) {
      if (V::kind(j) == ClearanceKind::Ideal) continue;
      pressed.q(QJ + V::group(j)) = 1.001 * m.bearing[j].clearance;
      pressed.q(QJ + V::group(j) + 1) = 0.0;
      pressed.v(NB + V::group(j) + 1) = 1e-3;
    }
    pressed.in_contact.fill(true);
    pressed.v0.fill(1e-3);
    c.derivative_us = std::max(c.derivative_us, medianUs([&] { forwardDynamics(m, d, pressed, u); }));
    const auto pressed_substep = [&] { rk4(m, d, pressed, u, m.integrator.substep, d.trial); };
    const double pressed_us = medianUs(pressed_substep);
    c.unit_us = std::max(c.unit_us, pressed_us);
    c.cold_us = std::max(c.cold_us, medianUs(pressed_substep, 1, evict) - pressed_us);
  }
  c.cold_us = std::max(0.0, c.cold_us);
  return c;
}

}  // namespace

TickBudget measureTickBudget(const Scene& sc, const Config& c) {
  const Model& m = sc.model;
  TickBudget b;
  const UnitCosts uc = dispatchVariant(m, [&](auto tag) { return unitCosts<decltype(tag)>(m, sc.run); });
  b.derivative_us = uc.derivative_us;
  b.steps_per_tick = std::max(1, checkConfig(sc, c).steps_per_tick);
  b.substep_cap = m.hasClearance() ? substepCap(m) : 1;  // without clearance a step is one RK4 step
  b.evals_per_substep = dispatchVariant(m, [&](auto tag) { return derivativesPerUnit<decltype(tag)>(m); });
  // A unit of more than an RK4 sub-step's 4 derivatives costs proportionally more.
  b.unit_us = uc.unit_us * std::max(1.0, b.evals_per_substep / 4.0);
  // The stepping's span also holds one read of the thread's CPU clock (a
  // system call), and its first unit finds the caches cold.
  b.cold_us = uc.cold_us;
  b.fixed_us = b.derivative_us + medianUs([] { (void)nowNs(CLOCK_THREAD_CPUTIME_ID); }) + b.cold_us;
  b.worst_tick_us = static_cast<double>(b.steps_per_tick) * b.substep_cap * b.unit_us + b.fixed_us;
  b.period_us = c.control_period * 1e6;
  return b;
}

std::string describeTickBudget(const TickBudget& b) {
  char line[480];
  std::snprintf(line, sizeof line,
                "worst-case tick %.0f us = %d steps x %d work units (cap) x %.2f us per unit (%d derivatives at most; "
                "an RK4 sub-step timed now) + %.2f us (the truth's derivative, %.2f us, cold caches, %.2f us, and a "
                "clock read); period %.0f us",
                b.worst_tick_us, b.steps_per_tick, b.substep_cap, b.unit_us, b.evals_per_substep, b.fixed_us,
                b.derivative_us, b.cold_us, b.period_us);
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
