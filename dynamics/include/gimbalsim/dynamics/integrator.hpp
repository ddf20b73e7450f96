// The step driver (docs/MODEL.md section 7): one call of step() advances
// the state by exactly h = sim.step. Away from contact that is one RK4 step
// (rk4.hpp). Near and in contact the step is split into sub-steps chosen by
// the scene's policy (substep_policy.hpp); a sub-step across which the
// contact or friction mode must switch is taken back and the switch located
// (event_locator.hpp), so the impact velocity v0 is measured at the true
// onset. Every RK4 evaluation counts against a cap, so the worst-case cost of
// a step is known. No heap allocation, no exception.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "gimbalsim/dynamics/event_locator.hpp"
#include "gimbalsim/dynamics/hermite.hpp"
#include "gimbalsim/dynamics/substep_policy.hpp"

namespace gimbalsim {

/// Longest sub-step in which a switch is located: the fixed policy's
/// sub-step (a far sub-step that reaches the bearing is retaken at it), the
/// adaptive policy's longest sub-step.
inline double longestLocated(const IntegratorParams& p) {
  if (p.substep_policy == SubstepPolicy::Adaptive) return p.substep_max > 0.0 ? std::fmin(p.substep_max, p.step) : p.step;
  return 1.01 * p.substep;  // FixedSubsteps::choose merges a sliver under 0.01 substep
}

/// Work-unit cap of one step (SubstepBudget): the plain sub-steps, room for
/// four located switches (each: its trials, its mode entry and the extra
/// sub-step it splits off), one far sub-step refused and one straddle
/// retaken down to event_tol. docs/MODEL.md 7.8.
inline int substepCap(const Model& m) {
  const IntegratorParams& p = m.integrator;
  if (p.max_substeps > 0) return p.max_substeps;
  const double longest = longestLocated(p);
  const int plain = static_cast<int>(std::ceil(p.step / p.substep - 1e-9));
  const int trials = locateIterations(p, longest);  // one switch located; also a straddle retaken to event_tol
  const int per_switch = trials + 2;                 // + its mode entry and the sub-step it splits off
  if (p.substep_policy == SubstepPolicy::Adaptive) return 2 * std::max(plain, 500) + 4 * per_switch + trials;
  return plain + 4 * per_switch + trials;
}

/// The most derivative evaluations (forwardDynamics calls) one work unit of
/// shape V takes: an RK4 sub-step 4 (adaptive: + the error estimate's and
/// the contact period's), a locator trial 3 (k1 reused), a mode entry the
/// onset velocity of each spatial end, the friction mode (coulomb_stick) and
/// the contact period; coulomb_stick adds the stick test to a sub-step and a
/// trial.
/// substepCap(m) x this is a true upper bound of one step's evaluations.
template <class V>
int derivativesPerUnit(const Model& m) {
  if constexpr (!V::kContact) {
    (void)m;
    return 4;
  } else {
    const IntegratorParams& p = m.integrator;
    const bool adaptive = p.substep_policy == SubstepPolicy::Adaptive;
    const int stick = V::kStick && m.bearing[1].friction == FrictionLaw::CoulombStick ? 1 : 0;
    int spatial_ends = 0;
    for (int e = 0; e < V::NC; ++e) spatial_ends += V::kind(V::endJoint(e)) == ClearanceKind::Spatial ? 1 : 0;
    const int period = adaptive || p.min_substeps_per_impact > 0.0 ? 1 : 0;
    const int rk4_step = adaptive ? 4 + 1 + 1 : 4 + stick;
    const int trial = 3 + stick;
    const int entry = spatial_ends + stick + period;
    return std::max({rk4_step, trial, entry});
  }
}

namespace detail {

template <class V>
void recordContactPeaks(Data<V>& d, double t) {
  RunStats& st = d.stats;
  for (int e = 0; e < V::NC; ++e) {
    const ContactEval& c = d.contact_k1[e];
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
    double& peak_j = st.peak_fn_joint[V::endJoint(e)];
    peak_j = std::max(peak_j, c.fn);
    st.peak_fn_end[e] = std::max(st.peak_fn_end[e], c.fn);
  }
  if constexpr (Data<V>::kSpatial) {
    // the tilt at the sub-step's start (d.spatial holds the last evaluation's)
    for (int j = 0; j < 2; ++j) {
      if (V::kind(j) == ClearanceKind::Spatial) st.max_tilt_joint[j] = std::max(st.max_tilt_joint[j], d.spatial[j].gamma);
    }
  }
}

enum class SubstepEnd : std::uint8_t { Accept, Switched, Failed, Retry };

/// After a sub-step of length dt from s to d.trial: locates a contact or
/// friction switch inside it (s then moved just past it, in its new mode:
/// Switched), or checks the penetration limit (Failed, r says why) and
/// leaves the trial to accept (Accept).
/// A sub-step from a free state whose end is free again may still have held
/// a whole contact: when its RK4 stages penetrated (the force applied with a
/// stale v0), or when the cubic Hermite interpolant of the gap through both
/// ends (values and rates) reaches the bearing in between. Such a sub-step is
/// refused (Retry) and the caller retakes it shorter, until the contact shows
/// at a sub-step's end or the sub-step is below event_tol.
/// trial_evaluated: d.contact and d.k_last hold f at d.trial (adaptive); the
/// switch is then guided by a Hermite-cubic first guess.
/// A sub-step longer than longestLocated() (a far one, fixed policy) whose
/// end changed side is refused too (Retry), so every switch is located in a
/// sub-step short enough for the cap's iteration count.
template <class V>
SubstepEnd handleSwitches(const Model& m, Data<V>& d, State<V>& s, const Input& u, double dt,
                          SubstepBudget& budget, bool trial_evaluated, StepResult& r) {
  const IntegratorParams& p = m.integrator;
  // An end free at both ends of the sub-step may have held a whole contact.
  if (dt > p.event_tol) {
    for (int e = 0; e < V::NC; ++e) {
      if (s.in_contact[e]) continue;
      const Gap g1 = endGap<V>(m, e, d.trial.q, d.trial.v);
      if (g1.delta > 0.0) continue;
      bool touched = d.stage_delta_max[e] > 0.0;
      if (!touched) {
        const Gap g0 = endGap<V>(m, e, s.q, s.v);
        touched = hermiteGapMax(dt, g0.delta, g0.rate, g1.delta, g1.rate) > 0.0;
      }
      if (touched) {
        ++d.stats.straddle_retries;
        return SubstepEnd::Retry;
      }
    }
  }
  int changed = 0;
  const GapSwitch<V> gap = gapSwitchOver(m, s, d.trial, changed);
  if (changed > 0) {
    if (dt > longestLocated(p)) {
      ++d.stats.straddle_retries;
      return SubstepEnd::Retry;
    }
    double guess = -1.0;
    if (trial_evaluated && gap.only >= 0) {
      const Gap g0 = endGap<V>(m, gap.only, s.q, s.v), g1 = endGap<V>(m, gap.only, d.trial.q, d.trial.v);
      guess = hermiteGapRoot(dt, g0.delta, g0.rate, g1.delta, g1.rate);
    }
    r = locateSwitch(m, d, s, u, dt, gap, budget, guess);
    if (r.ok() && !budget.takeEntry()) r = StepResult{StepStatus::SubstepCap, s.t};
    if (r.ok()) enterSwitchedEnds(m, d, s, u);
    return r.ok() ? SubstepEnd::Switched : SubstepEnd::Failed;
  }
  if constexpr (V::kStick) {
    if (frictionSwitched(m, d, d.trial, u, trial_evaluated)) {
      double guess = -1.0;
      if (trial_evaluated && s.friction_mode != 0) {
        // slipping: Hermite cubic of sigma v_t - floor, rates from f(s) = d.k[0]
        // and f(trial) = d.k_last
        const double sg = s.friction_mode;
        auto w = [&](const State<V>& x, const typename Data<V>::Deriv& f, double& rate) {
          rate = sg * (tangentialVelocity<V>(m, x.q, f.vd) + tangentialVelocityRateAtFixedV<V>(m, x.q, x.v));
          return sg * tangentialVelocity<V>(m, x.q, x.v) - s.vt_floor;
        };
        double r0 = 0.0, r1 = 0.0;
        const double w0 = w(s, d.k[0], r0), w1 = w(d.trial, d.k_last, r1);
        guess = hermiteGapRoot(dt, w0, r0, w1, r1);
      }
      r = locateSwitch(m, d, s, u, dt, FrictionSwitch<V>{m, d, u}, budget, guess);
      if (r.ok() && !budget.takeEntry()) r = StepResult{StepStatus::SubstepCap, s.t};
      if (r.ok()) {
        enterFrictionMode(m, d, s, u, false);
        ++d.stats.friction_switches;
      }
      return r.ok() ? SubstepEnd::Switched : SubstepEnd::Failed;
    }
  }
  for (int e = 0; e < V::NC; ++e) {
    const double limit = p.penetration_limit > 0.0 ? p.penetration_limit : m.bearing[V::endJoint(e)].clearance;
    const double delta = endGap<V>(m, e, d.trial.q, d.trial.v).delta;
    if (!(delta > limit)) continue;
    d.stats.max_penetration = std::fmax(d.stats.max_penetration, delta);
    r = StepResult{StepStatus::PenetrationLimit, d.trial.t, -1, -1, delta, V::endJoint(e)};
    return SubstepEnd::Failed;
  }
  return SubstepEnd::Accept;
}

/// Some end entered contact between the two sets of sides.
template <std::size_t N>
bool newOnset(const std::array<bool, N>& before, const std::array<bool, N>& after) {
  for (std::size_t e = 0; e < N; ++e) {
    if (!before[e] && after[e]) return true;
  }
  return false;
}

/// Same state up to time (the right-hand side does not depend on t; callers
/// snap s.t to the step grid, which may move it by an ulp).
template <class V>
bool sameState(const State<V>& a, const State<V>& b) {
  return a.q == b.q && a.v == b.v && a.in_contact == b.in_contact && a.v0 == b.v0 &&
         a.friction_mode == b.friction_mode && a.vt_floor == b.vt_floor;
}

/// One step of h under input u (held over the step) with sub-step policy P.
template <class V, class P>
StepResult stepWith(const Model& m, Data<V>& d, State<V>& s, const Input& u) {
  const IntegratorParams& p = m.integrator;
  const double t_end = s.t + p.step;
  SubstepBudget budget{0, substepCap(m)};
  double h_next = s.h_next;
  ++d.stats.steps;
  auto stop = [&](StepResult r) {
    d.stats.substeps += std::min(budget.used, budget.cap);  // a refused one was not taken
    d.stats.mode_entries += budget.entries;
    s.h_next = h_next;
    return r;
  };
  // d.k[0] = f(s) ready (after a rejection, or from the previous accepted sub-step).
  bool k1_ready = false;
  if constexpr (P::kReusesK1) {
    k1_ready = d.k_last_valid && d.k_last_tau == u.tau && sameState(d.k_last_state, s);
    if (k1_ready) {
      d.k[0] = d.k_last;
      d.contact_k1 = d.contact_last;
    }
    d.k_last_valid = false;
  }
  double dt_cap = p.step;  // shortened after a sub-step that held a whole contact
  while (true) {
    const double rem = t_end - s.t;
    if (rem <= 1e-12 * p.step) break;
    bool near = false;
    if constexpr (V::kContact) {
      for (int e = 0; e < V::NC && !near; ++e) {
        const Gap g = endGap<V>(m, e, s.q, s.v);
        near = s.in_contact[e] || g.delta + std::fmax(g.rate, 0.0) * rem > 0.0;
      }
    }
    double dt = P::choose(m, d, s, u, rem, near, h_next);
    if constexpr (V::kContact) dt = std::fmin(dt, dt_cap);
    if (!budget.take()) return stop({StepStatus::SubstepCap, s.t});
    rk4(m, d, s, u, dt, d.trial, k1_ready);
    k1_ready = P::kReusesK1;  // rk4 left f(s) in d.k[0]
    if (StepResult r = checkState(m, d.trial); !r.ok()) return stop(r);
    if constexpr (V::kContact) {
      if (near && !P::accept(m, d, u, dt, h_next)) continue;
      recordContactPeaks(d, s.t);
      const auto was_in_contact = s.in_contact;
      StepResult r;
      switch (handleSwitches(m, d, s, u, dt, budget, P::kReusesK1 && near, r)) {
        case SubstepEnd::Failed: return stop(r);
        case SubstepEnd::Retry:
          dt_cap = dt > longestLocated(p) ? p.substep : 0.5 * dt;  // a far sub-step: retaken near
          P::onRetry(dt_cap, h_next);
          continue;  // d.k[0] still holds f(s)
        case SubstepEnd::Switched:
          dt_cap = p.step;
          k1_ready = false;
          if (newOnset(was_in_contact, s.in_contact) && !P::onOnset(m, d, s, u, h_next, r)) {
            r.status = StepStatus::SubstepTooLong;
            r.time = s.t;
            return stop(r);
          }
          continue;
        case SubstepEnd::Accept: break;
      }
      s = d.trial;
      if (P::kReusesK1 && near) {
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
  s.h_next = h_next;
  if constexpr (P::kReusesK1) {
    if (k1_ready) {
      d.k_last = d.k[0];
      d.contact_last = d.contact_k1;
      d.k_last_state = s;
      d.k_last_tau = u.tau;
      d.k_last_valid = true;
    }
  }
  d.stats.substeps += budget.used;
  d.stats.mode_entries += budget.entries;
  d.stats.max_substeps_in_step = std::max(d.stats.max_substeps_in_step, budget.used + budget.entries);
  return {StepStatus::Ok, s.t};
}

}  // namespace detail

/// Advances s by one step h = sim.step under input u (held over the step).
/// On a status other than Ok, s is the last accepted state inside the step.
template <class V>
StepResult step(const Model& m, Data<V>& d, State<V>& s, const Input& u) {
  if (m.integrator.substep_policy == SubstepPolicy::Adaptive) {
    return detail::stepWith<V, AdaptiveSubsteps<V>>(m, d, s, u);
  }
  return detail::stepWith<V, FixedSubsteps<V>>(m, d, s, u);
}

/// Advances s from step k_from to step k_to of the run's grid (t = k h),
/// snapping s.t to the grid after each step so that long runs do not drift
/// in time. How simulate() and workprec step a run forward (the firmware
/// steps tick by tick, the stress check step by step with its monitors). On a status other than Ok, s is the last good state.
template <class V>
StepResult advanceSteps(const Model& m, Data<V>& d, State<V>& s, const Input& u, long long k_from,
                        long long k_to) {
  const double h = m.integrator.step;
  for (long long k = k_from + 1; k <= k_to; ++k) {
    if (const StepResult r = step(m, d, s, u); !r.ok()) return r;
    s.t = static_cast<double>(k) * h;
  }
  return {StepStatus::Ok, s.t};
}

// Every shape's step and forward dynamics are compiled once, in
// dynamics/src/shapes.inc; a file that runs a scene calls them.
#ifndef GIMBALSIM_COMPILING_SHAPES
#define GIMBALSIM_EXTERN_STEP(FL, K1, K2, FR)                                                              \
  extern template StepResult step<GIMBALSIM_SHAPE(FL, K1, K2, FR)>(                                      \
      const Model&, Data<GIMBALSIM_SHAPE(FL, K1, K2, FR)>&, State<GIMBALSIM_SHAPE(FL, K1, K2, FR)>&,      \
      const Input&);                                                                                       \
  extern template void forwardDynamics<GIMBALSIM_SHAPE(FL, K1, K2, FR)>(                                 \
      const Model&, Data<GIMBALSIM_SHAPE(FL, K1, K2, FR)>&, const State<GIMBALSIM_SHAPE(FL, K1, K2, FR)>&, \
      const Input&);
GIMBALSIM_FOR_EACH_SHAPE(GIMBALSIM_EXTERN_STEP)
#undef GIMBALSIM_EXTERN_STEP
#endif

}  // namespace gimbalsim
