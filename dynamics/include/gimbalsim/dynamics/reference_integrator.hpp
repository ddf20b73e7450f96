// Independent high-accuracy integrator for reference solutions: Boost.Odeint's
// adaptive Dormand-Prince 5(4) with dense output at tight tolerances, with the
// same contact switch location as the RK4 (the switch time is found on the
// dense-output interpolant, the integration restarts there with the contact
// memory updated). Not for real time: it allocates and is slow by design.
#pragma once

#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <vector>

#include "gimbalsim/dynamics/event_locator.hpp"
#include "gimbalsim/dynamics/integrator.hpp"

namespace gimbalsim {

struct ReferenceSettings {
  double abs_tol = 1e-12;
  double rel_tol = 1e-12;
  double event_tol = 1e-13;  ///< [s]
  double min_step = 1e-12;   ///< below this the run stops as stuck [s]
  long long max_steps = 1'000'000;  ///< more accepted steps than this: stuck
};

template <class V>
class ReferenceIntegrator {
 public:
  using Vec = std::vector<double>;
  static constexpr int NQ = V::NQ, NV = V::NV;

  ReferenceIntegrator(const Model& m, const Input& u, ReferenceSettings cfg = {})
      : m_(m), u_(u), cfg_(cfg), d_(m) {}

  /// Integrates s to time t_end (s.t < t_end). Returns false on NaN/Inf.
  bool advanceTo(State<V>& s, double t_end) {
    namespace ode = boost::numeric::odeint;
    if (!started_) restart(s);
    while (true) {
      if constexpr (V::kContact) {
        // A switch located in the last step: output times before it come from
        // this step's dense output, then the integration restarts there.
        if (pending_switch_) {
          if (pending_t_ >= t_end) break;
          applySwitch(pending_t_);
          continue;
        }
      }
      if (stepper_.current_time() >= t_end) break;
      const double t0 = stepper_.current_time();
      stepper_.do_step(std::ref(*this));
      const double t1 = stepper_.current_time();
      Vec x1 = stepper_.current_state();
      if (!finite(x1)) {
        failure_ = "non-finite state";
        return false;
      }
      if (stepper_.current_time_step() < cfg_.min_step || ++steps_ > cfg_.max_steps) {
        // Plain Coulomb friction's sign flip is a discontinuity an adaptive
        // method cannot step over: it would crawl forever.
        failure_ = "step size collapsed (below 1e-12 s, or more than 1e6 steps): a discontinuous "
                   "right-hand side such as plain Coulomb friction; use friction.law=coulomb_stick (the "
                   "set-valued law with located stick/slip) or ambrosio for reference solutions";
        return false;
      }
      // The scene's divergence limits hold for either integrator: a reference that ran past them would be
      // a solution the RK4 refuses to give.
      if (!withinLimits(toState(x1, t1))) return false;
      if constexpr (V::kContact) {
        if (switched(x1, t1)) {
          // Bisection on the dense output for the first switch in (t0, t1]:
          // the contact side, or (coulomb_stick) a v_t reversal or stick/slip.
          double lo = t0, hi = t1;
          Vec x(NQ + NV);
          while (hi - lo > cfg_.event_tol) {
            const double mid = 0.5 * (lo + hi);
            stepper_.calc_state(mid, x);
            (switched(x, mid) ? hi : lo) = mid;
          }
          pending_switch_ = true;
          pending_t_ = hi;
          continue;
        }
        recordContact(toState(x1, t1));
      }
      (void)t0;
    }
    Vec x(NQ + NV);
    stepper_.calc_state(t_end, x);
    s = toState(x, t_end);
    if (!finite(x)) {
      failure_ = "non-finite state";
      return false;
    }
    return true;
  }

  /// The ODE right-hand side, for odeint.
  void operator()(const Vec& x, Vec& dxdt, double t) {
    const State<V> s = toState(x, t);
    forwardDynamics(m_, d_, s, u_);
    dxdt.resize(NQ + NV);
    for (int i = 0; i < NQ; ++i) dxdt[i] = d_.qdot(i);
    for (int i = 0; i < NV; ++i) dxdt[NQ + i] = d_.vdot(i);
  }

  long long impacts() const { return d_.stats.impacts; }
  /// What the reference counts and tracks: impacts, separations, the last
  /// onset, and the contact peaks and penetration at every accepted step's
  /// end and switch; the RK4's step and sub-step counters stay 0.
  const RunStats& stats() const { return d_.stats; }
  /// coulomb_stick: located v_t reversals and stick/slip switches.
  long long frictionSwitches() const { return d_.stats.friction_switches; }
  /// Why advanceTo() returned false.
  const char* failure() const { return failure_; }
  /// The limit (sim.velocity_limit, sim.penetration_limit) that stopped it; Ok when none did.
  const StepResult& limit() const { return limit_; }

 private:
  using Stepper = boost::numeric::odeint::dense_output_runge_kutta<
      boost::numeric::odeint::controlled_runge_kutta<boost::numeric::odeint::runge_kutta_dopri5<Vec>>>;

  State<V> toState(const Vec& x, double t) const {
    State<V> s = mode_;
    s.t = t;
    for (int i = 0; i < NQ; ++i) s.q(i) = x[i];
    for (int i = 0; i < NV; ++i) s.v(i) = x[NQ + i];
    return s;
  }
  /// The contact peaks (the RK4's recordContactPeaks) at s, in its segment's mode.
  void recordContact(const State<V>& s) {
    forwardDynamics(m_, d_, s, u_);
    d_.contact_k1 = d_.contact;
    detail::recordContactPeaks(d_, s.t);
  }
  /// Restarts at a located switch time with the contact memory updated.
  void applySwitch(double t_switch) {
    Vec x(NQ + NV);
    stepper_.calc_state(t_switch, x);
    State<V> at = toState(x, t_switch);
    recordContact(at);
    if (gapSwitch().past(at, 0.0)) {
      enterSwitchedEnds(m_, d_, at, u_);
    } else if constexpr (V::kStick) {
      enterFrictionMode(m_, d_, at, u_, false);
      ++d_.stats.friction_switches;
    }
    pending_switch_ = false;
    restart(at);
  }

  /// Has the contact side or the friction mode's switch function changed
  /// between the current segment's start and x?
  bool switched(const Vec& x, double t) {
    const State<V> s = toState(x, t);
    return gapSwitch().past(s, 0.0) || FrictionSwitch<V>{m_, d_, u_}.past(s, 0.0);
  }
  /// The contact switch of the current segment: any end leaving its side.
  GapSwitch<V> gapSwitch() const {
    GapSwitch<V> sw{m_};
    for (int e = 0; e < V::NC; ++e) sw.started_in_contact[e] = mode_.in_contact[e];
    return sw;
  }
  /// sim.velocity_limit and sim.penetration_limit (0: the bearing's clearance), as the RK4 checks them.
  bool withinLimits(const State<V>& s) {
    limit_ = checkState<V>(m_, s);
    if (limit_.status == StepStatus::VelocityLimit) {
      failure_ = "a velocity exceeded sim.velocity_limit";
      return false;
    }
    limit_ = StepResult{};
    if constexpr (V::kContact) {
      const IntegratorParams& p = m_.integrator;
      for (int e = 0; e < V::NC; ++e) {
        const double cap = p.penetration_limit > 0.0 ? p.penetration_limit : m_.bearing[V::endJoint(e)].clearance;
        const double delta = endGap<V>(m_, e, s.q, s.v).delta;
        if (!(delta > cap)) continue;
        limit_ = StepResult{StepStatus::PenetrationLimit, s.t, -1, -1, delta, V::endJoint(e)};
        failure_ = "contact penetration exceeded sim.penetration_limit";
        return false;
      }
    }
    return true;
  }
  static bool finite(const Vec& x) {
    for (double e : x) {
      if (!std::isfinite(e)) return false;
    }
    return true;
  }
  void restart(State<V> s) {
    if constexpr (V::kFloating) s.q.template segment<4>(3).normalize();
    mode_ = s;
    Vec x(NQ + NV);
    for (int i = 0; i < NQ; ++i) x[i] = s.q(i);
    for (int i = 0; i < NV; ++i) x[NQ + i] = s.v(i);
    stepper_ = boost::numeric::odeint::make_dense_output(cfg_.abs_tol, cfg_.rel_tol,
                                                         boost::numeric::odeint::runge_kutta_dopri5<Vec>());
    stepper_.initialize(x, s.t, 1e-6);
    started_ = true;
  }

  const Model& m_;
  Input u_;
  ReferenceSettings cfg_;
  Data<V> d_;
  State<V> mode_;  ///< contact memory (in_contact, v0) of the current segment
  Stepper stepper_;
  bool started_ = false;
  bool pending_switch_ = false;  ///< a located switch at pending_t_ not yet applied
  double pending_t_ = 0.0;       ///< [s]
  long long steps_ = 0;
  const char* failure_ = "";
  StepResult limit_;  ///< the limit that stopped the run, Ok when none
};

}  // namespace gimbalsim
