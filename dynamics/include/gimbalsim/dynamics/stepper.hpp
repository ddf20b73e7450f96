// One interface for stepping a run forward on a time grid t_k = k * unit,
// shared by the fixed-step RK4 (the product: unit = sim.step) and the
// adaptive reference (any unit), and the loop that steps from row to row and
// hands each row's state to the caller (simulate(), workprec's fine pass; the
// Simulator steps on the caller's demand instead).
#pragma once

#include <algorithm>
#include <chrono>

#include "gimbalsim/dynamics/integrator.hpp"
#include "gimbalsim/dynamics/reference_integrator.hpp"

namespace gimbalsim {

/// How an advance ended: ok, or why not (a failed step of the RK4, with its
/// StepResult; the reference's own reason).
struct Advance {
  bool ok = true;
  StepResult step;               ///< the failed step (Rk4Stepper); the scene limit that stopped the reference
  const char* failure = "";      ///< the reference's reason (ReferenceStepper)
  double t_target = 0.0;         ///< [s] where the advance was going
};

/// The fixed-step RK4 with sub-stepping (integrator.hpp): the grid unit is sim.step.
template <class V>
class Rk4Stepper {
 public:
  Rk4Stepper(const Model& m, Data<V>& d, const Input& u) : m_(m), d_(d), u_(u) {}
  Advance advance(State<V>& s, long long k_from, long long k_to, double unit) {
    Advance a;
    a.t_target = static_cast<double>(k_to) * unit;
    a.step = advanceSteps(m_, d_, s, u_, k_from, k_to);  // unit == m_.integrator.step
    a.ok = a.step.ok();
    return a;
  }
  long long impacts() const { return d_.stats.impacts; }

 private:
  const Model& m_;
  Data<V>& d_;
  const Input& u_;
};

/// The adaptive Dormand-Prince reference (reference_integrator.hpp) on any grid.
template <class V>
class ReferenceStepper {
 public:
  ReferenceStepper(const Model& m, const Input& u) : integ_(m, u) {}
  Advance advance(State<V>& s, long long /*k_from*/, long long k_to, double unit) {
    Advance a;
    a.t_target = static_cast<double>(k_to) * unit;
    a.ok = integ_.advanceTo(s, a.t_target);
    if (!a.ok) a.failure = integ_.failure();
    if (!a.ok) a.step = integ_.limit();  // a scene limit reads as the RK4's does; Ok for the reference's own reasons
    return a;
  }
  long long impacts() const { return integ_.impacts(); }
  const RunStats& stats() const { return integ_.stats(); }

 private:
  ReferenceIntegrator<V> integ_;
};

/// The output loop of simulate() and workprec: from t = 0 to n_units * unit, a row every `every`
/// units (and the last at the end); after each advance, row(s, k) is called
/// with the grid index reached; false from it ends the loop (ok). The time
/// spent inside the stepper is added to *in_step when given. Returns how the
/// last advance ended.
template <class V, class Stepper, class Row>
Advance forEachRow(Stepper& stepper, State<V>& s, double unit, long long n_units, long long every, Row&& row,
                   std::chrono::steady_clock::duration* in_step = nullptr) {
  using Clock = std::chrono::steady_clock;
  for (long long k = 0; k < n_units;) {
    const long long k_next = std::min(k + every, n_units);
    const auto t0 = Clock::now();
    const Advance a = stepper.advance(s, k, k_next, unit);
    if (in_step) *in_step += Clock::now() - t0;
    if (!a.ok) return a;
    k = k_next;
    if (!row(s, k)) break;
  }
  return {};
}

}  // namespace gimbalsim
