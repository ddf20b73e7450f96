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
/// switches.
inline int substepCap(const Model& m) {
  const IntegratorParams& p = m.integrator;
  if (p.max_substeps > 0) return p.max_substeps;
  const int plain = static_cast<int>(std::ceil(p.step / p.substep - 1e-9));
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
  State<V>& st = d.stage;
  st = s;
  st.t = s.t + 0.5 * h;
  st.q = s.q + (0.5 * h) * k[0].qd;
  st.v = s.v + (0.5 * h) * k[0].vd;
  rk4Derivative(m, d, st, u, k[1]);
  st.q = s.q + (0.5 * h) * k[1].qd;
  st.v = s.v + (0.5 * h) * k[1].vd;
  rk4Derivative(m, d, st, u, k[2]);
  st.t = s.t + h;
  st.q = s.q + h * k[2].qd;
  st.v = s.v + h * k[2].vd;
  rk4Derivative(m, d, st, u, k[3]);
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

/// Advances s by one step h under input u (held over the step).
template <class V>
StepStatus step(const Model& m, Data<V>& d, State<V>& s, const Input& u) {
  const IntegratorParams& p = m.integrator;
  const double t_end = s.t + p.step;
  const int cap = substepCap(m);
  int n = 0;
  ++d.stats.steps;
  auto fail = [&](StepStatus why, double when) {
    d.fail_time = when;
    d.stats.substeps += n;
    return why;
  };
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
    }
    if (++n > cap) return fail(StepStatus::SubstepCap, s.t);
    rk4(m, d, s, u, dt, d.trial);
    if (const StepStatus st = checkState(m, d, d.trial); st != StepStatus::Ok) {
      return fail(st, d.trial.t);
    }
    if constexpr (V::kClearance) {
      detail::recordContactPeaks(d, s.t);
      const double g_hi0 = clearanceGap<V>(m, d.trial.q, d.trial.v).delta;
      if ((g_hi0 > 0.0) != s.in_contact) {
        // Locate the switch in (0, dt]: g(tau) = delta(rk4(s, tau)).
        double lo = 0.0, hi = dt;
        double g_lo = clearanceGap<V>(m, s.q, s.v).delta, g_hi = g_hi0;
        d.bracket_hi = d.trial;
        int side_kept = 0;  // Illinois: which end stayed twice in a row
        int it = 0;
        while (hi - lo > p.event_tol) {
          if (++it > p.max_event_iters) return fail(StepStatus::EventNotLocated, s.t);
          if (++n > cap) return fail(StepStatus::SubstepCap, s.t);
          double tau = lo - g_lo * (hi - lo) / (g_hi - g_lo);
          const double w = hi - lo;
          if (!(tau > lo + 0.01 * w && tau < hi - 0.01 * w) || it % 4 == 0) tau = 0.5 * (lo + hi);
          rk4(m, d, s, u, tau, d.trial, /*reuse_k1=*/true);
          ++d.stats.event_iterations;
          if (const StepStatus st = checkState(m, d, d.trial); st != StepStatus::Ok) {
            return fail(st, d.trial.t);
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
        } else {
          ++d.stats.separations;
        }
        continue;
      }
      const double limit =
          p.penetration_limit > 0.0 ? p.penetration_limit : m.contact.clearance;
      if (g_hi0 > limit) {
        d.fail_index = -1;
        return fail(StepStatus::PenetrationLimit, d.trial.t);
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
