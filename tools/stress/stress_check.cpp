#include "stress_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "gimbalsim/dynamics/integrator.hpp"
#include "gimbalsim/firmware_sim/plant_scene.hpp"
#include "gimbalsim/input/value_format.hpp"
#include "gimbalsim/scene/scene.hpp"

namespace gimbalsim::stress {

const char* verdictName(Verdict v) {
  switch (v) {
    case Verdict::Trustworthy: return "TRUSTWORTHY";
    case Verdict::Stopped: return "STOPPED";
    case Verdict::SilentlyWrong: return "SILENTLY_WRONG";
    case Verdict::StoppedUnclear: return "STOPPED_UNCLEAR";
    case Verdict::Refused: return "REFUSED";
  }
  return "?";
}

bool namesALimit(const RunStop& stop) {
  return *stop.key != '\0' || stop.kind == RunStop::Kind::NonFiniteOutput ||
         (stop.kind == RunStop::Kind::Step && stop.step.status == StepStatus::NonFinite);
}

double rowHertzEnergy(const Model& m, const Row& r) {
  auto spring = [](const ContactParams& c, double K, double delta) {
    return delta > 0.0 ? K * std::pow(delta, c.exponent + 1.0) / (c.exponent + 1.0) : 0.0;
  };
  double U = 0.0;
  const ContactParams &c1 = m.bearing[0], &c2 = m.bearing[1];
  if (m.joint1_kind == ClearanceKind::Planar) U += spring(c1, c1.K, r.delta1);
  if (m.joint1_kind == ClearanceKind::Spatial) U += spring(c1, 0.5 * c1.K, r.delta1_minus) + spring(c1, 0.5 * c1.K, r.delta1_plus);
  if (m.joint2_kind == ClearanceKind::Planar) U += spring(c2, c2.K, r.delta2);
  if (m.joint2_kind == ClearanceKind::Spatial) U += spring(c2, 0.5 * c2.K, r.delta2_minus) + spring(c2, 0.5 * c2.K, r.delta2_plus);
  return U;
}

namespace {
std::string sci(double x) { return formatSignificant(x, 3); }
}  // namespace

Outcome classify(const Scene& sc, const RunResult& run, const EnergyMonitor& e, const Bounds& b) {
  const Model& m = sc.model;
  // Relative measures stay meaningful when the scale is zero (nothing moved).
  const auto relative = &InvariantMonitor::relative;
  Outcome o;
  o.run = run;
  o.energy_rise_rel = relative(e.maxRise(), e.scale());
  o.energy_change_rel = relative(e.maxChange(), e.scale());
  o.energy_final_rel = relative(e.finalChange(), e.scale());
  o.max_penetration = std::max(run.stats.max_penetration, e.maxPenetration());
  // The run's deepest end against the larger bearing clearance (the
  // integrator's own guard holds each end to its joint's).
  const double clearance = std::max(m.joint2_kind != ClearanceKind::Ideal ? m.bearing[1].clearance : 0.0,
                                    m.joint1_kind != ClearanceKind::Ideal ? m.bearing[0].clearance : 0.0);
  o.penetration_limit = m.integrator.penetration_limit > 0.0 ? m.integrator.penetration_limit : clearance;
  o.substeps_per_second = run.t_end > 0.0 ? static_cast<double>(run.stats.substeps) / run.t_end : 0.0;
  if (m.floating_base) {
    o.momentum_rel_angular = relative(run.max_drift_angular, run.momentum_scale);
    o.momentum_rel_linear = relative(run.max_drift_linear, std::max(e.linearScale(), run.linear_scale));
  }
  if (!run.ok) {
    o.verdict = namesALimit(run.stop) ? Verdict::Stopped : Verdict::StoppedUnclear;
    o.reason = run.error;
    if (!(run.t_end > 0.0)) {
      // Stopped in its first step: a rate, drift or energy figure over no step is none (it read as 0, held,
      // pass 82); the penetration stays, seen at the initial state.
      const double nan = std::numeric_limits<double>::quiet_NaN();
      o.substeps_per_second = o.momentum_rel_linear = o.momentum_rel_angular = nan;
      o.energy_rise_rel = o.energy_change_rel = o.energy_final_rel = nan;
      o.reason += "; no sub-step rate, momentum drift or energy figure: the run stopped in its first step (no good "
                  "state after t = 0 s)";
    }
    return o;
  }
  std::string why;
  auto fail = [&](const std::string& s) { why += (why.empty() ? "" : "; ") + s; };
  bool finite = e.finite();
  for (double x : run.final_q) finite = finite && std::isfinite(x);
  for (double x : run.final_v) finite = finite && std::isfinite(x);
  if (!finite) fail("non-finite value in the output");
  if (std::fabs(run.t_end - sc.run.duration) > 1e-9 * std::max(1.0, sc.run.duration)) {
    fail("ended at t = " + sci(run.t_end) + " s, not at sim.duration");
  }
  if (m.floating_base) {
    if (!(o.momentum_rel_angular <= b.momentum_rel)) {
      fail("angular momentum drift " + sci(o.momentum_rel_angular) + " of its scale");
    }
    if (!(o.momentum_rel_linear <= b.momentum_rel)) {
      fail("linear momentum drift " + sci(o.momentum_rel_linear) + " of its scale");
    }
  }
  // A spatial joint's contact and couple do work the balance does not hold
  // (energyBalanceHeld): there the energy is not a check.
  if (energyBalanceHeld(m) && !(o.energy_rise_rel <= b.energy_rel)) {
    fail("energy balance E + U - W rose by " + sci(o.energy_rise_rel) + " of its scale");
  }
  if (energyBalanceHeld(m) && conservative(m) && !(o.energy_change_rel <= b.energy_rel)) {
    fail("conservative case: energy balance changed by " + sci(o.energy_change_rel) +
         " of its scale");
  }
  if (m.hasClearance() && !(o.max_penetration <= o.penetration_limit)) {
    fail("penetration " + sci(o.max_penetration) + " m beyond the limit");
  }
  o.verdict = why.empty() ? Verdict::Trustworthy : Verdict::SilentlyWrong;
  o.reason = why;
  return o;
}

Outcome runCase(const std::string& scene_path, const std::vector<std::string>& sets, const Bounds& b) {
  Scene sc;
  try {
    sc = firmware::loadPlantScene(scene_path, sets).scene;  // a sensors: section read, unused (open loop)
  } catch (const InputError& err) {
    Outcome o;
    o.verdict = Verdict::Refused;
    o.reason = err.what();
    return o;
  }
  EnergyMonitor e(sc.model, sc.run.torque);
  const Model& m = sc.model;
  const RunResult run = simulate(sc, [&](const Row& r) { e.feed(r, rowHertzEnergy(m, r)); });
  return classify(sc, run, e, b);
}

namespace {
template <class V>
double restitutionOf(const Model& m, double v_in) {
  // Measured on the paper's joint (planar joint 2, ideal joint 1) only.
  if constexpr (!(V::kKind1 == ClearanceKind::Ideal && V::kKind2 == ClearanceKind::Planar)) {
    (void)m, (void)v_in;
    return std::numeric_limits<double>::quiet_NaN();
  } else {
    constexpr int NB = V::NB;
    Data<V> d(m);
    State<V> s = initialState<V>(InitialParams{});
    s.q(State<V>::QJ + 1) = 0.0;
    s.q(State<V>::QJ + 2) = 0.0;
    s.v.setZero();
    s.v(NB + 1) = v_in;  // journal thrown along u1 from the centre
    const Input u;        // no torque
    double v_onset = 0.0;
    const long long n = std::llround(0.1 / m.integrator.step);  // 0.1 s
    for (long long k = 0; k < n; ++k) {
      const bool was = s.in_contact[0];
      const long long separations = d.stats.separations;
      if (!step(m, d, s, u).ok()) break;
      if (!was && s.in_contact[0]) v_onset = s.v0[0];
      if (d.stats.impacts >= 1 && d.stats.separations > separations) {
        // At most one sub-step past the located separation, in free flight.
        return -clearanceGap<V>(m, s.q, s.v).rate / v_onset;
      }
    }
    return std::numeric_limits<double>::quiet_NaN();
  }
}
}  // namespace

double effectiveRestitution(const Model& m, double v_in) {
  // One sub-step per step, so the state after the separating step is at most
  // one sub-step past the located separation.
  Model one = m;
  one.integrator.step = m.integrator.substep;
  return dispatchVariant(one, [&](auto tag) { return restitutionOf<decltype(tag)>(one, v_in); });
}

}  // namespace gimbalsim::stress
