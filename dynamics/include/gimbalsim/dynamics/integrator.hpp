// Fixed-step RK4 with contact sub-stepping and switch location (paper
// section 3). One call of step() advances the state by exactly h =
// model.integrator.step. Away from contact that is one RK4 step. Near and in
// contact the step is split into sub-steps of at most `substep`. A sub-step
// across which the penetration changes sign is taken back and the switch time
// is located (Illinois regula falsi, safeguarded by bisection) to `event_tol`,
// so the impact velocity v0 is measured at the true onset. Every RK4
// evaluation counts as a sub-step against a cap, so the worst-case cost of a
// step is known. No heap allocation, no exception.
#pragma once

#include <algorithm>
#include <cmath>

#include "gimbalsim/dynamics/forward_dynamics.hpp"

namespace gimbalsim {

/// Sub-step cap of one step: the plain sub-steps plus room for four located
/// switches (adaptive policy: at least 500 plain sub-steps, the tolerance
/// decides).
inline int substepCap(const Model& m) {
  const IntegratorParams& p = m.integrator;
  if (p.max_substeps > 0) return p.max_substeps;
  int plain = static_cast<int>(std::ceil(p.step / p.substep - 1e-9));
  if (p.substep_policy == SubstepPolicy::Adaptive) plain = std::max(plain, 500);
  return 2 * plain + 4 * p.max_event_iters + 4;
}

template <class V>
void rk4Derivative(const Model& m, Data<V>& d, const State<V>& s, const Input& u,
                   typename Data<V>::Deriv& k) {
  forwardDynamics(m, d, s, u);
  k.qd = d.qdot;
  k.vd = d.vdot;
}

/// One classical RK4 step of length h from s into out (input held fixed over
/// the four stages, quaternion renormalised at the end). With reuse_k1 the
/// first stage of the previous call from the same s is reused.
template <class V>
void rk4(const Model& m, Data<V>& d, const State<V>& s, const Input& u, double h,
         State<V>& out, bool reuse_k1 = false) {
  auto& k = d.k;
  if (!reuse_k1) {
    rk4Derivative(m, d, s, u, k[0]);
    if constexpr (V::kClearance) d.contact_k1 = d.contact;
  }
  // Deepest penetration the stages saw (a contact that begins and ends inside
  // the sub-step leaves both end points free; see handleSwitches()).
  [[maybe_unused]] double stage_delta = 0.0;
  if constexpr (V::kClearance) stage_delta = d.contact_k1.delta;
  State<V>& st = d.stage;
  st = s;
  st.t = s.t + 0.5 * h;
  st.q = s.q + (0.5 * h) * k[0].qd;
  st.v = s.v + (0.5 * h) * k[0].vd;
  rk4Derivative(m, d, st, u, k[1]);
  if constexpr (V::kClearance) stage_delta = std::fmax(stage_delta, d.contact.delta);
  st.q = s.q + (0.5 * h) * k[1].qd;
  st.v = s.v + (0.5 * h) * k[1].vd;
  rk4Derivative(m, d, st, u, k[2]);
  if constexpr (V::kClearance) stage_delta = std::fmax(stage_delta, d.contact.delta);
  st.t = s.t + h;
  st.q = s.q + h * k[2].qd;
  st.v = s.v + h * k[2].vd;
  rk4Derivative(m, d, st, u, k[3]);
  if constexpr (V::kClearance) d.stage_delta_max = std::fmax(stage_delta, d.contact.delta);
  out = s;
  out.t = s.t + h;
  out.q = s.q + (h / 6.0) * (k[0].qd + 2.0 * (k[1].qd + k[2].qd) + k[3].qd);
  out.v = s.v + (h / 6.0) * (k[0].vd + 2.0 * (k[1].vd + k[2].vd) + k[3].vd);
  if constexpr (V::kFloating) out.q.template segment<4>(3).normalize();
}

/// NaN/Inf or a velocity beyond the limit; sets d.fail_index.
template <class V>
StepStatus checkState(const Model& m, Data<V>& d, const State<V>& s) {
  for (int i = 0; i < V::NQ; ++i) {
    if (!std::isfinite(s.q(i))) {
      d.fail_index = -1 - i;  // negative: a q index
      return StepStatus::NonFinite;
    }
  }
  for (int i = 0; i < V::NV; ++i) {
    if (!std::isfinite(s.v(i))) {
      d.fail_index = i;
      return StepStatus::NonFinite;
    }
    if (std::fabs(s.v(i)) > m.integrator.velocity_limit) {
      d.fail_index = i;
      return StepStatus::VelocityLimit;
    }
  }
  return StepStatus::Ok;
}

namespace detail {
template <class V>
void recordContactPeaks(Data<V>& d, double t) {
  const ContactEval& c = d.contact_k1;
  RunStats& st = d.stats;
  if (c.fn > st.peak_fn) {
    st.peak_fn = c.fn;
    st.t_peak_fn = t;
  }
  const double f = std::hypot(c.fn, c.ft);
  if (f > st.peak_contact) {
    st.peak_contact = f;
    st.t_peak_contact = t;
  }
  st.max_penetration = std::max(st.max_penetration, c.delta);
}
}  // namespace detail

namespace detail {

/// coulomb_stick: has a friction switch happened between the segment's start
/// (whose mode x carries) and x? Slip: v_t changed sign against the mode.
/// Stick: the force needed to stick exceeds mu F_n. contact_at_x: d.contact
/// already holds forwardDynamics() at x (else it is evaluated here).
template <class V>
bool frictionSwitched(const Model& m, Data<V>& d, const State<V>& x, const Input& u, bool contact_at_x) {
  if constexpr (!V::kFriction) {
    return false;
  } else {
    if (m.contact.friction != FrictionLaw::CoulombStick || !x.in_contact) return false;
    if (x.friction_mode != 0) return x.friction_mode * tangentialVelocity<V>(m, x.q, x.v) < x.vt_floor;
    if (!contact_at_x) forwardDynamics(m, d, x, u);
    return std::fabs(d.contact.ft_required) > m.contact.mu * d.contact.fn;
  }
}

/// coulomb_stick: sets the friction mode to continue with from x, a state just
/// past a located switch (or a contact onset), x.friction_mode the mode before.
template <class V>
void enterFrictionMode(const Model& m, Data<V>& d, State<V>& x, const Input& u, bool onset) {
  const double vt = tangentialVelocity<V>(m, x.q, x.v);
  int mode = 0;
  if (onset && vt != 0.0) {
    mode = vt > 0.0 ? 1 : -1;
  } else {
    State<V>& probe = d.stage;
    probe = x;
    probe.friction_mode = 0;
    forwardDynamics(m, d, probe, u);
    mode = consistentFrictionMode(m, d);
    if (!onset && mode != 0 && mode == x.friction_mode) mode = 0;  // crossed within the tolerance
    if (!onset && mode == 0 && x.friction_mode == 0) mode = d.contact.ft_required > 0.0 ? -1 : 1;
  }
  x.friction_mode = mode;
  x.vt_floor = std::fmin(0.0, mode * vt);
}

/// Locates the first contact switch (penetration sign change) in (0, dt] of
/// the sub-step from s (Illinois regula falsi, bisection safeguard) and moves
/// s just past it with the contact memory updated. d.k[0] must be f(s).
/// guess (in (0, dt), else unused): a close estimate of the switch time; it
/// is tried first and then a point 1e-3 dt beyond it on the side of the root,
/// so the bracket shrinks to ~1e-3 dt in two evaluations.
template <class V>
StepStatus locateGapSwitch(const Model& m, Data<V>& d, State<V>& s, const Input& u, double dt, double g_hi0,
                           int& n, int cap, double guess = -1.0) {
  const IntegratorParams& p = m.integrator;
  double lo = 0.0, hi = dt;
  double g_lo = clearanceGap<V>(m, s.q, s.v).delta, g_hi = g_hi0;
  d.bracket_hi = d.trial;
  int side_kept = 0;  // Illinois: which end stayed twice in a row
  int it = 0;
  const bool guided = guess > 0.0 && guess < dt;
  while (hi - lo > p.event_tol) {
    if (++it > p.max_event_iters) return StepStatus::EventNotLocated;
    if (++n > cap) return StepStatus::SubstepCap;
    double tau = lo - g_lo * (hi - lo) / (g_hi - g_lo);
    const double w = hi - lo;
    if (!(tau > lo + 0.01 * w && tau < hi - 0.01 * w) || it % 4 == 0) tau = 0.5 * (lo + hi);
    if (guided && it == 1) tau = guess;
    if (guided && it == 2) {
      const double off = std::fmax(1e-3 * dt, 0.5 * p.event_tol);
      tau = hi == guess ? guess - off : guess + off;
      if (!(tau > lo && tau < hi)) tau = 0.5 * (lo + hi);
    }
    rk4(m, d, s, u, tau, d.trial, /*reuse_k1=*/true);
    ++d.stats.event_iterations;
    if (const StepStatus st = checkState(m, d, d.trial); st != StepStatus::Ok) {
      d.fail_time = d.trial.t;
      return st;
    }
    const double g = clearanceGap<V>(m, d.trial.q, d.trial.v).delta;
    if ((g > 0.0) != s.in_contact) {
      hi = tau;
      g_hi = g;
      d.bracket_hi = d.trial;
      if (side_kept == -1) g_lo *= 0.5;
      side_kept = -1;
    } else {
      lo = tau;
      g_lo = g;
      if (side_kept == 1) g_hi *= 0.5;
      side_kept = 1;
    }
  }
  s = d.bracket_hi;
  s.in_contact = !s.in_contact;
  if (s.in_contact) {
    s.v0 = clearanceGap<V>(m, s.q, s.v).rate;  // impact velocity at onset
    ++d.stats.impacts;
    d.stats.last_onset_time = s.t;
    if constexpr (V::kFriction) {
      if (m.contact.friction == FrictionLaw::CoulombStick) enterFrictionMode(m, d, s, u, true);
    }
  } else {
    ++d.stats.separations;
    s.friction_mode = 0;
    s.vt_floor = 0.0;
  }
  return StepStatus::Ok;
}

/// coulomb_stick: locates a friction switch in (0, dt] of the sub-step from s
/// by bisection (the switch functions v_t and mu F_n - |F_t required| are
/// checked as predicates) and moves s just past it in its new friction mode.
template <class V>
StepStatus locateFrictionSwitch(const Model& m, Data<V>& d, State<V>& s, const Input& u, double dt, int& n,
                                int cap, double guess = -1.0) {
  const IntegratorParams& p = m.integrator;
  double lo = 0.0, hi = dt;
  d.bracket_hi = d.trial;
  int it = 0;
  const bool guided = guess > 0.0 && guess < dt;  // as in locateGapSwitch()
  while (hi - lo > p.event_tol) {
    if (++it > p.max_event_iters) return StepStatus::EventNotLocated;
    if (++n > cap) return StepStatus::SubstepCap;
    double tau = 0.5 * (lo + hi);
    if (guided && it == 1) tau = guess;
    if (guided && it == 2) {
      const double off = std::fmax(1e-3 * dt, 0.5 * p.event_tol);
      tau = hi == guess ? guess - off : guess + off;
      if (!(tau > lo && tau < hi)) tau = 0.5 * (lo + hi);
    }
    rk4(m, d, s, u, tau, d.trial, /*reuse_k1=*/true);
    ++d.stats.event_iterations;
    if (const StepStatus st = checkState(m, d, d.trial); st != StepStatus::Ok) {
      d.fail_time = d.trial.t;
      return st;
    }
    if (frictionSwitched(m, d, d.trial, u, false)) {
      hi = tau;
      d.bracket_hi = d.trial;
    } else {
      lo = tau;
    }
  }
  s = d.bracket_hi;
  enterFrictionMode(m, d, s, u, false);
  ++d.stats.friction_switches;
  return StepStatus::Ok;
}

/// Root in (0, h) of the cubic Hermite interpolant of the penetration through
/// (0, g0, r0) and (h, g1, r1) (g0, g1 of opposite sides), or -1.
inline double hermiteGapRoot(double h, double g0, double r0, double g1, double r1) {
  auto g = [&](double x) {
    const double t = x / h, t2 = t * t, t3 = t2 * t;
    return (2 * t3 - 3 * t2 + 1) * g0 + (t3 - 2 * t2 + t) * h * r0 + (-2 * t3 + 3 * t2) * g1 + (t3 - t2) * h * r1;
  };
  double lo = 0.0, hi = h, glo = g0;
  if (!((g0 > 0.0) != (g1 > 0.0))) return -1.0;
  for (int i = 0; i < 60 && hi - lo > 1e-6 * h; ++i) {  // bisection, no dynamics evaluated
    const double mid = 0.5 * (lo + hi), gm = g(mid);
    if ((gm > 0.0) == (glo > 0.0)) {
      lo = mid;
      glo = gm;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

/// Largest value over [0, h] of the cubic Hermite interpolant of the gap
/// through (0, g0, r0) and (h, g1, r1) (rates r = d(gap)/dt).
inline double hermiteGapMax(double h, double g0, double r0, double g1, double r1) {
  // p(x) = a x^3 + b x^2 + c x + d on x = t / h in [0, 1]
  const double a = 2.0 * g0 + h * r0 - 2.0 * g1 + h * r1;
  const double b = -3.0 * g0 - 2.0 * h * r0 + 3.0 * g1 - h * r1;
  const double c = h * r0;
  auto p = [&](double x) { return ((a * x + b) * x + c) * x + g0; };
  double best = std::fmax(g0, g1);
  // p'(x) = 3a x^2 + 2b x + c
  const double qa = 3.0 * a, qb = 2.0 * b;
  if (qa == 0.0) {
    if (qb != 0.0) {
      const double x = -c / qb;
      if (x > 0.0 && x < 1.0) best = std::fmax(best, p(x));
    }
    return best;
  }
  const double disc = qb * qb - 4.0 * qa * c;
  if (disc < 0.0) return best;
  const double sq = std::sqrt(disc);
  for (const double x : {(-qb - sq) / (2.0 * qa), (-qb + sq) / (2.0 * qa)}) {
    if (x > 0.0 && x < 1.0) best = std::fmax(best, p(x));
  }
  return best;
}

enum class SubstepEnd : std::uint8_t { Accept, Switched, Failed, Retry };

/// After a sub-step from s to d.trial: locates a contact or friction switch
/// inside it (s then moved just past it: Switched), or checks the penetration
/// limit (Failed with why/when) and leaves the trial to accept (Accept).
/// A sub-step from a free state whose end is free again may still have held
/// a whole contact: when its RK4 stages penetrated (the force applied with a
/// stale v0), or when the cubic Hermite interpolant of the gap through both
/// ends (values and rates) reaches the bearing in between (an impact between
/// the stage times, not seen at all). Such a sub-step is refused (Retry) and
/// the caller retakes it shorter, until the contact shows at a sub-step's
/// end or the sub-step is below event_tol.
/// contact_at_trial: d.contact holds forwardDynamics() at d.trial.
template <class V>
SubstepEnd handleSwitches(const Model& m, Data<V>& d, State<V>& s, const Input& u, double dt, int& n, int cap,
                          bool contact_at_trial, StepStatus& why, double& when) {
  const IntegratorParams& p = m.integrator;
  const Gap g1 = clearanceGap<V>(m, d.trial.q, d.trial.v);
  const double g_hi0 = g1.delta;
  StepStatus st = StepStatus::Ok;
  if (!s.in_contact && !(g_hi0 > 0.0) && dt > p.event_tol) {
    bool touched = d.stage_delta_max > 0.0;
    if (!touched) {
      const Gap g0 = clearanceGap<V>(m, s.q, s.v);
      touched = hermiteGapMax(dt, g0.delta, g0.rate, g1.delta, g1.rate) > 0.0;
    }
    if (touched) {
      ++d.stats.straddle_retries;
      return SubstepEnd::Retry;
    }
  }
  if ((g_hi0 > 0.0) != s.in_contact) {
    double guess = -1.0;
    if (contact_at_trial) {  // adaptive: guide the location with the gap's Hermite cubic
      const Gap g0 = clearanceGap<V>(m, s.q, s.v);
      guess = hermiteGapRoot(dt, g0.delta, g0.rate, g1.delta, g1.rate);
    }
    st = locateGapSwitch(m, d, s, u, dt, g_hi0, n, cap, guess);
  } else if (frictionSwitched(m, d, d.trial, u, contact_at_trial)) {
    double guess = -1.0;
    if (contact_at_trial && s.friction_mode != 0) {
      // adaptive, slipping: Hermite cubic of sigma v_t - floor, rates from
      // f(s) = d.k[0] and f(trial) = d.k_last
      const double sg = s.friction_mode;
      auto w = [&](const State<V>& x, const typename Data<V>::Deriv& f, double& rate) {
        rate = sg * (tangentialVelocity<V>(m, x.q, f.vd) + tangentialVelocityRateAtFixedV<V>(m, x.q, x.v));
        return sg * tangentialVelocity<V>(m, x.q, x.v) - s.vt_floor;
      };
      double r0 = 0.0, r1 = 0.0;
      const double w0 = w(s, d.k[0], r0), w1 = w(d.trial, d.k_last, r1);
      guess = hermiteGapRoot(dt, w0, r0, w1, r1);
    }
    st = locateFrictionSwitch(m, d, s, u, dt, n, cap, guess);
  } else {
    const double limit = p.penetration_limit > 0.0 ? p.penetration_limit : m.contact.clearance;
    if (!(g_hi0 > limit)) return SubstepEnd::Accept;
    d.stats.max_penetration = std::fmax(d.stats.max_penetration, g_hi0);
    d.fail_index = -1;
    why = StepStatus::PenetrationLimit;
    when = d.trial.t;
    return SubstepEnd::Failed;
  }
  if (st == StepStatus::Ok) return SubstepEnd::Switched;
  why = st;
  when = st == StepStatus::NonFinite || st == StepStatus::VelocityLimit ? d.fail_time : s.t;
  return SubstepEnd::Failed;
}

/// First guess of the adaptive sub-step near contact from the physics: a
/// twentieth of the Hertz contact period T = pi sqrt(m_eff / k_lin), k_lin =
/// n K delta_max^(n-1) at the penetration an impact at the approach speed
/// reaches, m_eff = 1 / (n^T M^-1 n) from the last factor of M.
template <class V>
double physicalSubstepGuess(const Model& m, Data<V>& d, const State<V>& s) {
  constexpr int NB = V::NB, QJ = State<V>::QJ;
  const ContactParams& c = m.contact;
  const double ex = s.q(QJ + 1), ey = s.q(QJ + 2), e = std::hypot(ex, ey);
  double m_eff = m.shaft2.mass;
  if (e > 0.0 && d.L(0, 0) > 0.0) {
    typename Data<V>::VecV nv = Data<V>::VecV::Zero(), x;
    nv(NB + 1) = ex / e;
    nv(NB + 2) = ey / e;
    choleskySolveFactored<V::NV>(d.L, nv, x);
    const double inv = nv.dot(x);
    if (inv > 0.0 && std::isfinite(inv)) m_eff = 1.0 / inv;
  }
  const double v = std::fmax(std::fmax(std::fabs(clearanceGap<V>(m, s.q, s.v).rate), std::fabs(s.v0)), 1e-3);
  // K delta^(n+1) / (n+1) = m v^2 / 2
  const double n = c.exponent;
  const double delta = std::pow(0.5 * (n + 1.0) * m_eff * v * v / c.K, 1.0 / (n + 1.0));
  const double k_lin = n * c.K * std::pow(delta, n - 1.0);
  return 3.141592653589793 * std::sqrt(m_eff / k_lin) / 20.0;
}

/// Local error of the sub-step just taken (d.k[3] at the RK4 stage, k5 = f at
/// the result): RK4 minus its embedded third-order companion with weights
/// (1/6, 1/3, 1/3, 0, 1/6) is h/6 (k4 - k5); max over coordinates of
/// |err_i| / (1 + |y_i|).
template <class V>
double embeddedError(const Data<V>& d, const typename Data<V>::Deriv& k5, const State<V>& y, double h) {
  double e = 0.0;
  for (int i = 0; i < V::NQ; ++i) {
    e = std::fmax(e, std::fabs(d.k[3].qd(i) - k5.qd(i)) / (1.0 + std::fabs(y.q(i))));
  }
  for (int i = 0; i < V::NV; ++i) {
    e = std::fmax(e, std::fabs(d.k[3].vd(i) - k5.vd(i)) / (1.0 + std::fabs(y.v(i))));
  }
  return e * h / 6.0;
}

/// Fixed policy, at a located impact onset s: is sim.substep short enough for
/// the impact? Its duration is estimated as the Hertz contact period (20 x
/// physicalSubstepGuess(), which uses the factor of M left in d.L by the last
/// evaluation, near s); recorded in stats.min_impact_duration and
/// d.fail_detail. False when it spans fewer than min_substeps_per_impact
/// sub-steps.
template <class V>
bool impactResolved(const Model& m, Data<V>& d, const State<V>& s) {
  const IntegratorParams& p = m.integrator;
  if (!(p.min_substeps_per_impact > 0.0)) return true;
  const double duration = 20.0 * physicalSubstepGuess(m, d, s);
  RunStats& st = d.stats;
  if (st.min_impact_duration == 0.0 || duration < st.min_impact_duration) st.min_impact_duration = duration;
  d.fail_detail = duration;
  return p.substep * p.min_substeps_per_impact <= duration;
}

/// Same state up to time (the right-hand side does not depend on t; callers
/// snap s.t to the step grid, which may move it by an ulp).
template <class V>
bool sameState(const State<V>& a, const State<V>& b) {
  return a.q == b.q && a.v == b.v && a.in_contact == b.in_contact && a.v0 == b.v0 &&
         a.friction_mode == b.friction_mode && a.vt_floor == b.vt_floor;
}

}  // namespace detail

/// Advances s by one step h under input u (held over the step) with
/// sub-steps chosen by local error control (sim.substep_policy adaptive):
/// near and in contact each sub-step is accepted when the embedded RK4/3
/// error estimate is within sim.substep_tol (the first guess from the contact
/// period, then the usual controller h * clamp(0.9 (tol/err)^(1/4), 0.2, 4)),
/// rejected sub-steps count against the cap too. The last sub-step lands
/// exactly on the step's end; contact and friction switches are located to
/// event_tol as in the fixed policy. f at the end of an accepted sub-step is
/// the next sub-step's first stage (also across steps, while the state and
/// the input are unchanged).
template <class V>
StepStatus stepAdaptive(const Model& m, Data<V>& d, State<V>& s, const Input& u) {
  const IntegratorParams& p = m.integrator;
  const double t_end = s.t + p.step;
  const double h_max = p.substep_max > 0.0 ? std::fmin(p.substep_max, p.step) : p.step;
  const int cap = substepCap(m);
  int n = 0;
  ++d.stats.steps;
  auto fail = [&](StepStatus why, double when) {
    d.fail_time = when;
    d.stats.substeps += std::min(n, cap);  // the refused one was not taken
    return why;
  };
  // d.k[0] = f(s) ready (after a rejection, or from the previous accepted sub-step).
  bool k1_ready = d.k_last_valid && d.k_last_tau == u.tau && detail::sameState(d.k_last_state, s);
  if (k1_ready) {
    d.k[0] = d.k_last;
    d.contact_k1 = d.contact_last;
  }
  d.k_last_valid = false;
  double dt_cap = p.step;  // shortened after a sub-step that held a whole contact
  while (true) {
    const double rem = t_end - s.t;
    if (rem <= 1e-12 * p.step) break;
    double dt = rem;
    bool near = false;
    if constexpr (V::kClearance) {
      const Gap g = clearanceGap<V>(m, s.q, s.v);
      near = s.in_contact || g.delta + std::fmax(g.rate, 0.0) * rem > 0.0;
      if (near) {
        if (!(d.h_next > 0.0)) {
          d.h_next = std::fmin(h_max, std::fmax(p.substep_min, detail::physicalSubstepGuess(m, d, s)));
        }
        dt = std::fmin(d.h_next, h_max);
        if (dt >= rem * (1.0 - 1e-9)) {
          dt = rem;
        } else if (dt > 0.5 * rem) {
          dt = 0.5 * rem;  // two even sub-steps instead of a long and a sliver
        }
      }
    }
    dt = std::fmin(dt, dt_cap);
    if (++n > cap) return fail(StepStatus::SubstepCap, s.t);
    rk4(m, d, s, u, dt, d.trial, k1_ready);
    k1_ready = true;  // rk4 left f(s) in d.k[0]
    if (const StepStatus st = checkState(m, d, d.trial); st != StepStatus::Ok) {
      return fail(st, d.trial.t);
    }
    if constexpr (V::kClearance) {
      if (near) {
        rk4Derivative(m, d, d.trial, u, d.k_last);  // k5 (same mode as the sub-step)
        const double ratio = detail::embeddedError(d, d.k_last, d.trial, dt) / p.substep_tol;
        const double grow = ratio > 0.0 ? 0.9 * std::pow(ratio, -0.25) : 4.0;
        if (ratio > 1.0 && dt > p.substep_min) {
          ++d.stats.rejected_substeps;
          d.h_next = std::fmax(p.substep_min, dt * std::fmax(0.2, grow));
          continue;
        }
        if (ratio > 1.0) ++d.stats.forced_substeps;
        const double h_new = dt * std::fmin(4.0, std::fmax(0.2, grow));
        // A sub-step cut short to land on the grid does not shrink the next.
        d.h_next = std::fmin(h_max, std::fmax(p.substep_min, dt < d.h_next && ratio <= 1.0
                                                                   ? std::fmax(h_new, d.h_next)
                                                                   : h_new));
        d.contact_last = d.contact;
      }
      detail::recordContactPeaks(d, s.t);
      const bool was_in_contact = s.in_contact;
      StepStatus why = StepStatus::Ok;
      double when = 0.0;
      switch (detail::handleSwitches(m, d, s, u, dt, n, cap, near, why, when)) {
        case detail::SubstepEnd::Failed: return fail(why, when);
        case detail::SubstepEnd::Retry:
          dt_cap = 0.5 * dt;
          d.h_next = std::fmin(d.h_next > 0.0 ? d.h_next : dt_cap, dt_cap);
          continue;  // d.k[0] still holds f(s)
        case detail::SubstepEnd::Switched:
          dt_cap = p.step;
          if (!was_in_contact && s.in_contact) {
            d.h_next = std::fmin(d.h_next, std::fmax(p.substep_min, detail::physicalSubstepGuess(m, d, s)));
          }
          k1_ready = false;
          continue;
        case detail::SubstepEnd::Accept: break;
      }
      s = d.trial;
      if (near) {
        d.k[0] = d.k_last;  // first stage of the next sub-step
        d.contact_k1 = d.contact_last;
      } else {
        k1_ready = false;
      }
    } else {
      s = d.trial;
      k1_ready = false;
    }
  }
  s.t = t_end;
  if (k1_ready) {
    d.k_last = d.k[0];
    d.contact_last = d.contact_k1;
    d.k_last_state = s;
    d.k_last_tau = u.tau;
    d.k_last_valid = true;
  }
  d.stats.substeps += n;
  d.stats.max_substeps_in_step = std::max(d.stats.max_substeps_in_step, n);
  return StepStatus::Ok;
}

/// Advances s by one step h under input u (held over the step).
template <class V>
StepStatus step(const Model& m, Data<V>& d, State<V>& s, const Input& u) {
  if (m.integrator.substep_policy == SubstepPolicy::Adaptive) return stepAdaptive(m, d, s, u);
  const IntegratorParams& p = m.integrator;
  const double t_end = s.t + p.step;
  const int cap = substepCap(m);
  int n = 0;
  ++d.stats.steps;
  auto fail = [&](StepStatus why, double when) {
    d.fail_time = when;
    d.stats.substeps += std::min(n, cap);  // the refused one was not taken
    return why;
  };
  double dt_cap = p.step;  // shortened after a sub-step that held a whole contact
  while (true) {
    const double rem = t_end - s.t;
    if (rem <= 1e-12 * p.step) break;
    double dt = rem;
    if constexpr (V::kClearance) {
      // Sub-step while in contact or when the gap may close within the step.
      const Gap g = clearanceGap<V>(m, s.q, s.v);
      if (s.in_contact || g.delta + std::fmax(g.rate, 0.0) * rem > 0.0) {
        dt = std::fmin(p.substep, rem);
        if (rem - dt < 0.01 * p.substep) dt = rem;
      }
      dt = std::fmin(dt, dt_cap);
    }
    if (++n > cap) return fail(StepStatus::SubstepCap, s.t);
    rk4(m, d, s, u, dt, d.trial);
    if (const StepStatus st = checkState(m, d, d.trial); st != StepStatus::Ok) {
      return fail(st, d.trial.t);
    }
    if constexpr (V::kClearance) {
      detail::recordContactPeaks(d, s.t);
      StepStatus why = StepStatus::Ok;
      double when = 0.0;
      const bool was_in_contact = s.in_contact;
      switch (detail::handleSwitches(m, d, s, u, dt, n, cap, false, why, when)) {
        case detail::SubstepEnd::Failed: return fail(why, when);
        case detail::SubstepEnd::Retry: dt_cap = 0.5 * dt; continue;
        case detail::SubstepEnd::Switched:
          dt_cap = p.step;
          if (!was_in_contact && s.in_contact && !detail::impactResolved(m, d, s)) {
            return fail(StepStatus::SubstepTooLong, s.t);
          }
          continue;
        case detail::SubstepEnd::Accept: break;
      }
    }
    s = d.trial;
  }
  s.t = t_end;
  d.stats.substeps += n;
  d.stats.max_substeps_in_step = std::max(d.stats.max_substeps_in_step, n);
  return StepStatus::Ok;
}

}  // namespace gimbalsim
