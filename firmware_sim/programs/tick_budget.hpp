// The worst-case compute of one tick, bounded by the work cap and measured
// at start: firmware_sim times a work unit of its variant (an RK4 sub-step
// pressed into the bearing, a whole free step) and multiplies by the most
// units a tick may take, so a bench engineer knows before running whether the
// plant can miss a deadline by itself. docs/bench.md "Worst-case compute per
// tick".
#pragma once

#include <string>

#include "app.hpp"

namespace gimbalsim::firmware {

struct TickBudget {
  double derivative_us = 0.0;   ///< [us] one forward-dynamics evaluation (the slower of free and in contact)
  double unit_us = 0.0;         ///< [us] one work unit: the slower of an RK4 sub-step pressed and a free step,
                                ///< scaled by evals_per_substep / 4 when a unit may take more derivatives
  double cold_us = 0.0;         ///< [us] per tick: what the first unit costs more with cold caches and TLB
  double fixed_us = 0.0;        ///< [us] per tick: the truth's derivative, cold_us and one read of the thread CPU clock
  int steps_per_tick = 1;       ///< T / sim.step
  int substep_cap = 0;          ///< work units per step at most (sim.max_substeps or its automatic value)
  int evals_per_substep = 4;    ///< derivatives per work unit at most (derivativesPerUnit)
  double worst_tick_us = 0.0;   ///< [us] steps_per_tick substep_cap unit_us + fixed_us
  double period_us = 0.0;       ///< [us] control period
  bool exceeds() const noexcept { return worst_tick_us > period_us; }
};

/// Times a work unit at the scene's initial state (and, with clearance,
/// pressed into the bearing) and derives the bound.
TickBudget measureTickBudget(const Scene& sc, const Config& c);

/// The start line, and the warning naming the keys when the bound exceeds the period ("" if not).
std::string describeTickBudget(const TickBudget& b);
std::string tickBudgetWarning(const TickBudget& b);

}  // namespace gimbalsim::firmware
