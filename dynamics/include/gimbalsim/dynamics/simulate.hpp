// Whole-run driver: picks the Variant once from the Model, steps to the end,
// hands each output row to a sink. The hot loop is the templated step().
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "gimbalsim/dynamics/data.hpp"
#include "gimbalsim/dynamics/step_result.hpp"
#include "gimbalsim/dynamics/model.hpp"
#include "gimbalsim/dynamics/observables.hpp"
#include "gimbalsim/dynamics/run_spec.hpp"
#include "gimbalsim/dynamics/variant.hpp"

namespace gimbalsim {

/// Names of the q and v coordinates of a variant (for diagnostics and output).
std::vector<std::string> coordinateNamesQ(const Model& m);
std::vector<std::string> coordinateNamesV(const Model& m);

/// The one message of a failed step, for every driver (simulate, the closed
/// loop, Python): when, why, in which coordinate, and the figures of the
/// limit it broke ("simulation stopped at t = T s: " + describeStopCause).
std::string describeStop(const Model& m, const StepResult& st);

/// describeStop without its time: why, in which coordinate, the limit's figures.
std::string describeStopCause(const Model& m, const StepResult& st);

/// When a driver that keeps its last good state (the bench, the closed loop)
/// stopped, as every reader of its run says it (%.6g): "0.02804 s, its last
/// good state (a sub-step from it failed)" or "(its step to t = 0.029 s failed)".
std::string describeStopWhen(double last_good_s, const StepResult& st);

/// Why the reference integrator cannot run m, or "" when it can: plain
/// Coulomb friction on a bearing with play flips sign where no adaptive step
/// can cross, so the run would crawl for seconds and then stop (MODEL.md 7.10).
std::string referenceRefusal(const Model& m);

/// Why a run ended before its duration (RunResult::stop): read these fields,
/// not the message.
struct RunStop {
  enum class Kind : std::uint8_t {
    None,             ///< the run reached its duration
    Step,             ///< a step failed: see step (status, time, coordinate)
    NonFiniteOutput,  ///< an output row held NaN or Inf
    Invariant,        ///< sim.momentum_tol or sim.energy_tol broken at an output row
    Reference,        ///< the reference integrator gave up
    Interrupted,      ///< the caller's stop predicate asked, after an output row (a signal)
  };
  Kind kind = Kind::None;
  StepResult step;
  const char* key = "";  ///< the scene key of the limit that stopped the run ("" when none names it)
  double time = 0.0;     ///< [s]
};

enum class IntegratorKind { Rk4, Reference };

struct RunResult {
  bool ok = true;
  /// Which integrator ran: the Reference has no RK4 steps or sub-steps
  /// (stats.steps, substeps, ... stay 0 and the summary leaves them out).
  IntegratorKind integrator = IntegratorKind::Rk4;
  RunStop stop;                ///< why the run ended early (when !ok)
  std::string error;           ///< the same for people: what stopped the run, when and in what
  double t_end = 0.0;          ///< last good time [s]
  RunStats stats;
  bool in_contact_at_end = false;
  std::vector<double> final_q, final_v;
  double max_drift_linear = 0.0;   ///< max |P(t) - P(0)| over output rows [N s]
  double max_drift_angular = 0.0;  ///< max |L(t) - L(0)| [N m s]
  double momentum_scale = 0.0;     ///< max over rows of sum |L_body|: drift reference [N m s]
  double linear_scale = 0.0;       ///< lower bound of max sum |p_body|: drift reference [N s]
  double energy_rise_rel = 0.0;    ///< max rise of the energy balance / its scale (invariants.hpp) [-]
  double peak_joint2_force = 0.0, t_peak_joint2_force = 0.0;  ///< [N], [s]
  long long rows = 0;
  double wall_seconds = 0.0;       ///< whole run including the sink
  double step_seconds = 0.0;       ///< inside step() only
};

/// Runs the scene's constant torques (run.torque) for run.duration. The sink sees every
/// row (including t = 0); a non-finite row, or one that breaks
/// sim.momentum_tol or sim.energy_tol (InvariantMonitor), stops the run before
/// reaching it (ok = false, error says when and which key).
/// IntegratorKind::Reference uses the adaptive Dormand-Prince reference
/// (reference_integrator.hpp) instead of the fixed-step RK4.
/// `stop`, when given, is asked after each row the sink took; true ends the
/// run there (RunStop::Kind::Interrupted), the step itself never sees it.
RunResult simulate(const Scene& scene, const std::function<void(const Row&)>& sink,
                   IntegratorKind kind = IntegratorKind::Rk4, const std::function<bool()>& stop = {});

}  // namespace gimbalsim
