// Locating a switch inside a sub-step (docs/MODEL.md 7.5, 7.6): the time at
// which a switch function changes side, to sim.event_tol, by re-integrating
// the sub-step from its start to trial lengths. One locator for every switch:
// the contact gap (a signed value: Illinois regula falsi, safeguarded by
// bisection) and the coulomb_stick slip/stick predicates (bisection). Every
// trial is projected into a shrinking ball about the bracket's midpoint
// (the ITP method's projection), so a switch is located within
// locateIterations() trials whatever the switch function does.
#pragma once

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <limits>

#include "gimbalsim/dynamics/contact_modes.hpp"
#include "gimbalsim/dynamics/rk4.hpp"

namespace gimbalsim {

/// Work units taken against the cap of one step: every RK4 sub-step or
/// locator trial (used), and the mode entry after each located switch
/// (entries, whose evaluations of the derivative are not an RK4), so the
/// worst-case cost of a step is known (integrator.hpp, derivativesPerUnit).
struct SubstepBudget {
  int used = 0;
  int cap = 0;
  int entries = 0;
  bool take() noexcept { return ++used + entries <= cap; }
  bool takeEntry() noexcept { return used + ++entries <= cap; }
};

/// Trials beyond bisection's count that the locator may spend on regula
/// falsi (ITP's n0): two let it approach the root from one side and then step
/// across, which typically locates a contact switch in 3 trials.
inline constexpr int kLocateSlack = 2;

namespace detail {
/// ITP's trial budget n_max for a bracket of length dt: bisection's
/// ceil(log2(dt / event_tol)) plus kLocateSlack (docs/MODEL.md 7.5).
inline int locateBudget(const IntegratorParams& p, double dt) {
  const double halvings = dt > p.event_tol ? std::ceil(std::log2(dt / p.event_tol)) : 0.0;
  return static_cast<int>(std::fmin(halvings, 4096.0)) + kLocateSlack;  // fmin: an infinite dt stays an int
}
}  // namespace detail

/// The most trials locating a switch in a sub-step of length dt can take:
/// locateBudget, at most sim.max_event_iters.
inline int locateIterations(const IntegratorParams& p, double dt) {
  return std::min(detail::locateBudget(p, dt), p.max_event_iters);
}

/// NaN/Inf, or a velocity beyond sim.velocity_limit, in s.
template <class V>
StepResult checkState(const Model& m, const State<V>& s) {
  StepResult r;
  r.time = s.t;
  for (int i = 0; i < V::NQ; ++i) {
    if (!std::isfinite(s.q(i))) {
      r.status = StepStatus::NonFinite;
      r.q_index = i;
      return r;
    }
  }
  for (int i = 0; i < V::NV; ++i) {
    if (!std::isfinite(s.v(i)) || std::fabs(s.v(i)) > m.integrator.velocity_limit) {
      r.status = std::isfinite(s.v(i)) ? StepStatus::VelocityLimit : StepStatus::NonFinite;
      r.v_index = i;
      return r;
    }
  }
  r.status = StepStatus::Ok;
  return r;
}

/// The contact switch: some end's penetration delta changes sign against
/// the side that end started the sub-step on. With one end changing side
/// over the sub-step its delta is the signed switch function; with several,
/// the largest of the ends' signed distances past their side (delta for an
/// end that started free, -delta for one in contact), positive once the
/// earliest end is past. Either is located by regula falsi.
template <class V>
struct GapSwitch {
  const Model& m;
  std::array<bool, Data<V>::NE> started_in_contact{};
  int only = -1;  ///< the one end whose side changed over the sub-step, or -1
  bool signedValue() const { return true; }
  double value(const State<V>& x) const {
    if (only >= 0) return endGap<V>(m, only, x.q, x.v).delta;
    double past_by = -std::numeric_limits<double>::infinity();
    for (int e = 0; e < V::NC; ++e) {
      const double delta = endGap<V>(m, e, x.q, x.v).delta;
      past_by = std::fmax(past_by, started_in_contact[e] ? -delta : delta);
    }
    return past_by;
  }
  bool past(const State<V>& x, double g) const {
    for (int e = 0; e < V::NC; ++e) {
      const double ge = e == only ? g : endGap<V>(m, e, x.q, x.v).delta;
      if ((ge > 0.0) != started_in_contact[e]) return true;
    }
    return false;
  }
};

/// The contact switch of a sub-step from s (its ends' sides) to `end`, and
/// how many ends changed side over it.
template <class V>
GapSwitch<V> gapSwitchOver(const Model& m, const State<V>& s, const State<V>& end, int& changed) {
  GapSwitch<V> sw{m};
  changed = 0;
  for (int e = 0; e < V::NC; ++e) {
    sw.started_in_contact[e] = s.in_contact[e];
    if ((endGap<V>(m, e, end.q, end.v).delta > 0.0) != s.in_contact[e]) {
      sw.only = e;
      ++changed;
    }
  }
  if (changed > 1) sw.only = -1;
  return sw;
}

/// coulomb_stick: a v_t reversal while slipping, or the end of stick.
template <class V>
struct FrictionSwitch {
  bool signedValue() const { return false; }
  const Model& m;
  Data<V>& d;
  const Input& u;
  double value(const State<V>& /*x*/) const { return 0.0; }
  bool past(const State<V>& x, double /*g*/) const { return frictionSwitched(m, d, x, u, false); }
};

/// Locates the first switch of sw in (0, dt] of the sub-step from s, whose
/// full-length end is d.trial (past the switch), and moves s to the first
/// state found past it (within event_tol); the caller then sets the new
/// mode. d.k[0] must hold f(s). guess (in (0, dt), else unused): a close
/// estimate of the switch time; it is tried first and then a point 1e-3 dt
/// beyond it on the side of the root, so the bracket shrinks to ~1e-3 dt in
/// two evaluations.
template <class V, class Switch>
StepResult locateSwitch(const Model& m, Data<V>& d, State<V>& s, const Input& u, double dt, const Switch& sw,
                        SubstepBudget& budget, double guess = -1.0) {
  const IntegratorParams& p = m.integrator;
  double lo = 0.0, hi = dt;
  double g_lo = 0.0, g_hi = 0.0;
  const bool is_signed = sw.signedValue();
  if (is_signed) {
    g_lo = sw.value(s);
    g_hi = sw.value(d.trial);
  }
  d.bracket_hi = d.trial;
  int side_kept = 0;  // Illinois: which end stayed twice in a row
  int it = 0;
  const bool guided = guess > 0.0 && guess < dt;
  // ITP's guarantee: trial k lies within radius_k of the midpoint, so the
  // bracket after it is at most event_tol 2^(n_max - k - 1) long.
  const int n_max = detail::locateBudget(p, dt);
  StepResult r;
  while (hi - lo > p.event_tol) {
    r.time = s.t;
    if (it >= n_max) break;  // event_tol long up to round-off: the guarantee is met
    if (++it > p.max_event_iters) return r.status = StepStatus::EventNotLocated, r;
    if (!budget.take()) return r.status = StepStatus::SubstepCap, r;
    const double mid = 0.5 * (lo + hi);
    double tau = mid;
    if (is_signed) {
      const double w = hi - lo, rf = lo - g_lo * w / (g_hi - g_lo);
      // At least half a tolerance from either end: once one end sits next to the root,
      // regula falsi lands on it again, and the step across closes the bracket instead.
      if (rf > lo && rf < hi && it % 4 != 0) tau = std::clamp(rf, lo + 0.5 * p.event_tol, hi - 0.5 * p.event_tol);
    }
    if (guided && it == 1) tau = guess;
    if (guided && it == 2) {
      const double off = std::fmax(1e-3 * dt, 0.5 * p.event_tol);
      tau = hi == guess ? guess - off : guess + off;
      if (!(tau > lo && tau < hi)) tau = mid;
    }
    const double radius = std::fmax(0.0, std::ldexp(0.5 * p.event_tol, n_max - it + 1) - 0.5 * (hi - lo));
    tau = std::clamp(tau, mid - radius, mid + radius);
    rk4(m, d, s, u, tau, d.trial, /*reuse_k1=*/true);
    ++d.stats.event_iterations;
    if (r = checkState(m, d.trial); !r.ok()) return r;
    const double g = sw.value(d.trial);
    if (std::getenv("DBG_LOC")) std::fprintf(stderr, "it %d signed %d tau/dt %.12f w/tol %.1f g %.3e past %d\n", it, (int)is_signed, tau / dt, (hi - lo) / p.event_tol, g, (int)sw.past(d.trial, g));
    if (sw.past(d.trial, g)) {
      hi = tau;
      d.bracket_hi = d.trial;
      if (is_signed) {
        g_hi = g;
        if (side_kept == -1) g_lo *= 0.5;
        side_kept = -1;
      }
    } else {
      lo = tau;
      if (is_signed) {
        g_lo = g;
        if (side_kept == 1) g_hi *= 0.5;
        side_kept = 1;
      }
    }
  }
  s = d.bracket_hi;
  r.status = StepStatus::Ok;
  return r;
}

}  // namespace gimbalsim
