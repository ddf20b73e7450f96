// Numerical stability stress checks (issue 4): run one case of the stress
// grid and classify it. Shared by the gimbalsim_stress tool and the ctest
// subset (tests/stress/), so both check exactly the same thing.
//
// A case is a scene plus "key=value" overrides. Its verdict:
//   Trustworthy    finished, no NaN, momentum held (floating base), the energy
//                  balance never rising (see EnergyMonitor), penetration
//                  within the limit;
//   Stopped        the run stopped with a diagnostic naming the limit it hit;
//   SilentlyWrong  finished "ok" but a check failed: a failure;
//   StoppedUnclear stopped without naming a limit: a failure;
//   Refused        the scene was refused (a bad case definition): a failure.
#pragma once

#include <string>
#include <vector>

#include "gimbalsim/dynamics/invariants.hpp"
#include "gimbalsim/dynamics/observables.hpp"
#include "gimbalsim/dynamics/simulate.hpp"

namespace gimbalsim::stress {

enum class Verdict { Trustworthy, Stopped, SilentlyWrong, StoppedUnclear, Refused };
const char* verdictName(Verdict v);
/// Trustworthy and Stopped are acceptable outcomes; the rest are failures.
inline bool acceptable(Verdict v) { return v == Verdict::Trustworthy || v == Verdict::Stopped; }

/// Bounds of a trustworthy run. Relative quantities are fractions of the
/// scales defined in EnergyMonitor / Outcome.
struct Bounds {
  double momentum_rel = 1e-9;  ///< max |L(t) - L(0)| / L scale, same for P [-]
  double energy_rel = 1e-6;    ///< max rise of E + U - W over any earlier value / energy scale [-]
};

/// The energy balance and momentum along the output rows, as simulate()
/// checks them (gimbalsim/dynamics/invariants.hpp).
using EnergyMonitor = InvariantMonitor;

/// Everything measured about one case.
struct Outcome {
  Verdict verdict = Verdict::Refused;
  std::string reason;          ///< why (the failed checks, or the stop message)
  RunResult run;               ///< as simulate() returned it
  double momentum_rel_angular = 0.0;  ///< max |L - L0| / RunResult::momentum_scale (floating only)
  double momentum_rel_linear = 0.0;   ///< max |P - P0| / EnergyMonitor::linearScale (floating only)
  double energy_rise_rel = 0.0;       ///< EnergyMonitor::maxRise / scale
  double energy_change_rel = 0.0;     ///< EnergyMonitor::maxChange / scale
  double energy_final_rel = 0.0;      ///< (B(end) - B(0)) / scale: < 0 dissipated
  double max_penetration = 0.0;       ///< [m]
  double penetration_limit = 0.0;     ///< [m]
  double substeps_per_second = 0.0;   ///< RK4 evaluations per simulated second [1/s]
};

/// The stop names a limit the integrator enforces (its scene key), or NaN/Inf
/// and where: read from the stop's codes, never from its message.
bool namesALimit(const RunStop& stop);

/// The energy in every contact end's Hertz spring at an output row [J]:
/// K delta^(n+1) / (n+1) per end, K / 2 at each end of a spatial joint
/// (as the integrator's hertzEnergy at the row's state).
double rowHertzEnergy(const Model& m, const Row& r);

/// Pure classification of a finished (or stopped) run.
Outcome classify(const Scene& sc, const RunResult& run, const EnergyMonitor& e, const Bounds& b);

/// Loads the scene with the overrides and runs it with the RK4 integrator.
Outcome runCase(const std::string& scene_path, const std::vector<std::string>& sets, const Bounds& b);

/// Effective coefficient of restitution of one isolated impact: fixed base, no
/// torque, no friction, the journal thrown radially at v_in [m/s] from the
/// bearing centre; returns -(normal velocity at separation) / (at onset),
/// measured at the located switch times. Uses the model's contact law and
/// integrator settings (set a fine sim.substep). Returns NaN when the impact
/// did not complete within 0.1 s or the run stopped.
double effectiveRestitution(const Model& m, double v_in);

}  // namespace gimbalsim::stress
