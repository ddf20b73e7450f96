// How the contact sub-step is chosen (sim.substep_policy), as policies of the
// one step driver in integrator.hpp (docs/MODEL.md 7.3, 7.4):
//  - FixedSubsteps: sim.substep near and in contact; an impact too short for
//    it stops the run (sim.min_substeps_per_impact);
//  - AdaptiveSubsteps: local error control with the embedded RK4/3 pair to
//    sim.substep_tol, first guess from the Hertz contact period, and f at the
//    end of an accepted sub-step reused as the next k1 (first same as last).
// A new policy implements the same five members.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "gimbalsim/dynamics/rk4.hpp"

namespace gimbalsim {

/// The Hertz contact period at the onset state s: T = pi sqrt(m_eff / k_lin),
/// k_lin = n K delta_max^(n-1) at the penetration an impact at the approach
/// speed reaches (K delta^(n+1) / (n+1) = m_eff v^2 / 2), m_eff =
/// 1 / (J M^-1 J^T) with J the generalised direction of the end's normal
/// force, M factored at s itself. The shortest over the ends (a spatial end
/// has stiffness K / 2), returned as T / 20, the adaptive first guess.
template <class V>
double contactPeriodOver20(const Model& m, Data<V>& d, const State<V>& s, const Input& u) {
  forwardDynamics(m, d, s, u);  // leaves the factor of M(s.q) in d.mass
  double period = std::numeric_limits<double>::infinity();
  for (int e = 0; e < V::NC; ++e) {
    const int j = V::endJoint(e);
    const ContactParams& c = m.bearing[j];
    const bool spatial = V::kind(j) == ClearanceKind::Spatial;
    typename Data<V>::VecV nv = Data<V>::VecV::Zero(), x;
    if (!endNormalDirection<V>(m, d, s, e, nv) || !d.mass.ok) nv.setZero();
    double m_eff = m.shaft2.mass;
    if (!nv.isZero(0.0)) {
      solveMass(d.mass, nv, x);
      const double inv = nv.dot(x);
      if (inv > 0.0 && std::isfinite(inv)) m_eff = 1.0 / inv;
    }
    const double v = std::fmax(std::fmax(std::fabs(endGap<V>(m, e, s.q, s.v).rate), std::fabs(s.v0[e])), 1e-3);
    const double n = c.exponent, K = spatial ? 0.5 * c.K : c.K;
    const double delta = std::pow(0.5 * (n + 1.0) * m_eff * v * v / K, 1.0 / (n + 1.0));
    const double k_lin = n * K * std::pow(delta, n - 1.0);
    period = std::fmin(period, 3.141592653589793 * std::sqrt(m_eff / k_lin) / 20.0);
  }
  return period;
}

template <class V>
struct FixedSubsteps {
  static constexpr bool kReusesK1 = false;

  /// The sub-step to try from s with rem left in the step (near: in contact,
  /// or the gap may close within the step).
  static double choose(const Model& m, Data<V>&, const State<V>&, const Input&, double rem, bool near,
                       double& /*h_next*/) {
    if (!near) return rem;
    const double h = m.integrator.substep;
    double dt = std::fmin(h, rem);
    if (rem - dt < 0.01 * h) dt = rem;
    return dt;
  }
  /// After a trial sub-step of length dt near contact: keep it?
  static bool accept(const Model&, Data<V>&, const Input&, double /*dt*/, double& /*h_next*/) { return true; }
  /// The sub-step held a whole contact and is retaken no longer than dt_cap.
  static void onRetry(double /*dt_cap*/, double& /*h_next*/) {}
  /// At a located impact onset s: false stops the step. The impact's
  /// duration (the Hertz contact period) must span sim.min_substeps_per_impact
  /// sub-steps; it goes to stats.min_impact_duration and r.detail.
  static bool onOnset(const Model& m, Data<V>& d, const State<V>& s, const Input& u, double& /*h_next*/,
                      StepResult& r) {
    const IntegratorParams& p = m.integrator;
    if (!(p.min_substeps_per_impact > 0.0)) return true;
    const double duration = 20.0 * contactPeriodOver20(m, d, s, u);
    RunStats& st = d.stats;
    if (st.min_impact_duration == 0.0 || duration < st.min_impact_duration) st.min_impact_duration = duration;
    r.detail = duration;
    return p.substep * p.min_substeps_per_impact <= duration;
  }
};

template <class V>
struct AdaptiveSubsteps {
  static constexpr bool kReusesK1 = true;

  static double maxSubstep(const IntegratorParams& p) {
    return p.substep_max > 0.0 ? std::fmin(p.substep_max, p.step) : p.step;
  }
  static double choose(const Model& m, Data<V>& d, const State<V>& s, const Input& u, double rem, bool near,
                       double& h_next) {
    if constexpr (!V::kContact) {
      return rem;  // never near: no contact to resolve
    } else {
      if (!near) return rem;
      const IntegratorParams& p = m.integrator;
      const double h_max = maxSubstep(p);
      if (!(h_next > 0.0)) h_next = std::fmin(h_max, std::fmax(p.substep_min, contactPeriodOver20(m, d, s, u)));
      double dt = std::fmin(h_next, h_max);
      if (dt >= rem * (1.0 - 1e-9)) {
        dt = rem;
      } else if (dt > 0.5 * rem) {
        dt = 0.5 * rem;  // two even sub-steps instead of a long and a sliver
      }
      return dt;
    }
  }
  /// Error control: k5 = f(trial) into d.k_last (the next k1 when accepted);
  /// the usual controller h * clamp(0.9 (tol/err)^(1/4), 0.2, 4).
  static bool accept(const Model& m, Data<V>& d, const Input& u, double dt, double& h_next) {
    const IntegratorParams& p = m.integrator;
    const double h_max = maxSubstep(p);
    evalDerivative(m, d, d.trial, u, d.k_last);  // k5 (same mode as the sub-step)
    const double ratio = embeddedError(d, d.k_last, d.trial, dt) / p.substep_tol;
    const double grow = ratio > 0.0 ? 0.9 * std::pow(ratio, -0.25) : 4.0;
    if (ratio > 1.0 && dt > p.substep_min) {
      ++d.stats.rejected_substeps;
      h_next = std::fmax(p.substep_min, dt * std::fmax(0.2, grow));
      return false;
    }
    if (ratio > 1.0) ++d.stats.forced_substeps;
    const double h_new = dt * std::fmin(4.0, std::fmax(0.2, grow));
    // A sub-step cut short to land on the grid does not shrink the next.
    h_next = std::fmin(h_max, std::fmax(p.substep_min, dt < h_next && ratio <= 1.0 ? std::fmax(h_new, h_next) : h_new));
    d.contact_last = d.contact;
    return true;
  }
  static void onRetry(double dt_cap, double& h_next) { h_next = std::fmin(h_next > 0.0 ? h_next : dt_cap, dt_cap); }
  static bool onOnset(const Model& m, Data<V>& d, const State<V>& s, const Input& u, double& h_next, StepResult&) {
    h_next = std::fmin(h_next, std::fmax(m.integrator.substep_min, contactPeriodOver20(m, d, s, u)));
    return true;
  }
};

}  // namespace gimbalsim
