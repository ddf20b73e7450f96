#include "gimbalsim/dynamics/simulate.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <utility>

#include "gimbalsim/dynamics/integrator.hpp"
#include "gimbalsim/dynamics/invariants.hpp"
#include "gimbalsim/dynamics/stepper.hpp"

namespace gimbalsim {


namespace {

/// The base's coordinates (floating base only), then the chain's, one group
/// per joint (variant.hpp): joint 1 [theta1] or [ecc1_x, ecc1_y, theta1]
/// (+ alpha1, beta1 before theta1 when spatial), joint 2 the same with
/// ecc_x, ecc_y, alpha2, beta2, theta2; each chain name after `rate`.
std::vector<std::string> coordinateNames(const Model& m, std::vector<std::string> base, const std::string& rate) {
  std::vector<std::string> n;
  if (m.floating_base) n = std::move(base);
  const auto group = [&](ClearanceKind kind, const std::string& ecc, const std::string& j) {
    if (kind != ClearanceKind::Ideal) {
      n.push_back(rate + ecc + "_x");
      n.push_back(rate + ecc + "_y");
    }
    if (kind == ClearanceKind::Spatial) {
      n.push_back(rate + "alpha" + j);
      n.push_back(rate + "beta" + j);
    }
    n.push_back(rate + "theta" + j);
  };
  group(m.joint1_kind, "ecc1", "1");
  group(m.joint2_kind, "ecc2", "2");
  return n;
}

}  // namespace

std::vector<std::string> coordinateNamesQ(const Model& m) {
  return coordinateNames(m, {"base_x", "base_y", "base_z", "base_qw", "base_qx", "base_qy", "base_qz"}, "");
}

std::vector<std::string> coordinateNamesV(const Model& m) {
  return coordinateNames(m,
                         {"base_wx", "base_wy", "base_wz", "base_vx(base frame)", "base_vy(base frame)",
                          "base_vz(base frame)"},
                         "d");
}

std::string describeStop(const Model& m, const StepResult& st) {
  std::ostringstream os;
  os << "simulation stopped at t = " << st.time << " s: " << describeStopCause(m, st);
  return os.str();
}

std::string describeStopWhen(double last_good_s, const StepResult& st) {
  // %.6g, as plot_bench and torque_replay read the truth CSV: a step that fails inside the control period
  // leaves the state a sub-step on (0.02804 s), which %.3f printed as the tick before it (pass 37)
  char text[160];
  if (st.time > last_good_s) {
    std::snprintf(text, sizeof text, "%.6g s, its last good state (its step to t = %.6g s failed)", last_good_s,
                  st.time);
  } else {
    std::snprintf(text, sizeof text, "%.6g s, its last good state (a sub-step from it failed)", last_good_s);
  }
  return text;
}

std::string describeStopCause(const Model& m, const StepResult& st) {
  std::ostringstream os;
  os << describe(st.status);
  const auto qn = coordinateNamesQ(m);
  const auto vn = coordinateNamesV(m);
  if (st.v_index >= 0 && st.v_index < static_cast<int>(vn.size())) os << " (in " << vn[st.v_index] << ")";
  if (st.q_index >= 0 && st.q_index < static_cast<int>(qn.size())) os << " (in " << qn[st.q_index] << ")";
  if (st.status == StepStatus::PenetrationLimit && (st.joint == 0 || st.joint == 1)) {
    const double c = m.bearing[st.joint].clearance;
    os << " (penetration " << st.detail << " m in joint " << st.joint + 1 << "'s bearing, clearance " << c << " m";
    if (m.integrator.penetration_limit > 0.0) {
      os << ", sim.penetration_limit " << m.integrator.penetration_limit << " m)";
    } else {  // the default limit: the contact pressed in deeper than the play is wide
      os << ", the default limit; a clearance below the penetration its load presses in is held by the "
            "contact's compliance, not its play: docs/MODEL.md 2.7 \"Where the play model holds\")";
    }
  }
  if (st.status == StepStatus::SubstepTooLong) {
    os << " (impact lasting about " << st.detail << " s, " << st.detail / m.integrator.substep
       << " sub-steps of " << m.integrator.substep << " s; sim.min_substeps_per_impact "
       << m.integrator.min_substeps_per_impact << ")";
  }
  return os.str();
}

std::string referenceRefusal(const Model& m) {
  for (int j = 0; j < 2; ++j) {
    const ContactParams& b = m.bearing[j];
    if (m.jointKind(j) != ClearanceKind::Ideal && b.friction == FrictionLaw::Coulomb && b.mu > 0.0) {
      return "joint " + std::to_string(j + 1) + "'s bearing has friction.law coulomb (plain Coulomb), whose sign "
             "flip stops the reference integrator at the first sliding contact; for a reference solution use "
             "friction.law=ambrosio, or coulomb_stick (a planar joint 2 with an ideal joint 1)";
    }
  }
  return "";
}

namespace {

/// The normal force at each contact end of V in row r (joint 1's ends
/// first, as RunStats::peak_fn_end).
template <class V>
std::array<double, 4> endForces(const Row& r) {
  std::array<double, 4> f{};
  auto put = [&f](int j, ClearanceKind k, double sum, double minus, double plus) {
    const int e = V::firstEnd(j);
    if (k == ClearanceKind::Planar) f[e] = sum;
    if (k == ClearanceKind::Spatial) f[e] = minus, f[e + 1] = plus;
  };
  put(0, V::kKind1, r.fn1, r.fn1_minus, r.fn1_plus);
  put(1, V::kKind2, r.fn2, r.fn2_minus, r.fn2_plus);
  return f;
}

template <class V>
RunResult run(const Model& m, const RunSpec& spec, const std::function<void(const Row&)>& sink, IntegratorKind kind,
              const std::function<bool()>& stop) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  RunResult res;
  Data<V> d(m);
  State<V> s = initialState<V>(spec.initial);
  Input u;
  u.tau = spec.torque;
  const long long n_steps = std::llround(spec.duration / m.integrator.step);
  const long long out_every = std::max<long long>(1, std::llround(spec.output_interval / m.integrator.step));
  Clock::duration in_step{0};
  InvariantMonitor inv(m, spec.torque);
  RunStats at_rows;  // the contact peaks at the output rows, merged into the stepper's below

  auto stopRun = [&](RunStop stop, const std::string& why) {
    res.ok = false;
    res.stop = stop;
    res.error = why;
  };
  auto emit = [&](const State<V>& st) -> bool {
    const Row r = observe(m, d, st, u);
    if (!rowFinite(r)) {
      std::ostringstream os;
      os << "non-finite output at t = " << st.t << " s";
      stopRun({RunStop::Kind::NonFiniteOutput, {}, "", st.t}, os.str());
      return false;
    }
    const Momentum mo = momentum(m, d, st);
    inv.feed(r, hertzEnergy<V>(m, st.q, st.v), mo.scale, mo.scale_linear);
    res.max_drift_linear = inv.maxDriftLinear();
    res.max_drift_angular = inv.maxDriftAngular();
    res.momentum_scale = inv.angularScale();
    res.linear_scale = inv.linearScale();
    res.energy_rise_rel = inv.energyRiseRel();
    if (const InvariantMonitor::Violation v = inv.violation()) {
      std::ostringstream os;
      os << "simulation stopped at t = " << st.t << " s: " << v.message;
      stopRun({RunStop::Kind::Invariant, {}, v.key, st.t}, os.str());
      return false;
    }
    at_rows.max_penetration = std::max({at_rows.max_penetration, r.delta1, r.delta2});
    // Peaks are per contact end (a spatial joint's fn column sums two ends).
    const std::array<double, 4> fe = endForces<V>(r);
    for (int e = 0; e < V::NC; ++e) {
      if (fe[e] > at_rows.peak_fn) {
        at_rows.peak_fn = fe[e];
        at_rows.t_peak_fn = r.t;
      }
      at_rows.peak_fn_end[e] = std::max(at_rows.peak_fn_end[e], fe[e]);
      at_rows.peak_fn_joint[V::endJoint(e)] = std::max(at_rows.peak_fn_joint[V::endJoint(e)], fe[e]);
    }
    at_rows.max_tilt_joint[0] = std::max(at_rows.max_tilt_joint[0], r.tilt1);
    at_rows.max_tilt_joint[1] = std::max(at_rows.max_tilt_joint[1], r.tilt2);
    if (r.joint2_force > res.peak_joint2_force) {
      res.peak_joint2_force = r.joint2_force;
      res.t_peak_joint2_force = r.t;
    }
    ++res.rows;
    res.t_end = st.t;
    sink(r);
    if (stop && stop()) {
      std::ostringstream os;
      os << "interrupted at t = " << st.t << " s";
      stopRun({RunStop::Kind::Interrupted, {}, "", st.t}, os.str());
      return false;
    }
    return true;
  };

  // One output loop for both integrators (stepper.hpp); each reports its own failure.
  auto rows = [&](auto& stepper) {
    if (!emit(s)) return;
    const Advance a = forEachRow(stepper, s, m.integrator.step, n_steps, out_every,
                                 [&](const State<V>& st, long long) { return emit(st); }, &in_step);
    if (a.ok) return;
    if (kind == IntegratorKind::Reference && a.step.ok()) {
      std::ostringstream os;
      os << "reference integration stopped before t = " << a.t_target << " s: " << a.failure;
      stopRun({RunStop::Kind::Reference, {}, "", s.t}, os.str());
    } else {
      stopRun({RunStop::Kind::Step, a.step, a.step.key(), a.step.time}, describeStop(m, a.step));
    }
  };
  res.integrator = kind;
  if (kind == IntegratorKind::Reference) {
    ReferenceStepper<V> ref(m, u);
    rows(ref);
    d.stats = ref.stats();  // its own counts and peaks; the RK4's step counters stay 0
  } else {
    Rk4Stepper<V> rk4(m, d, u);
    rows(rk4);
  }
  if constexpr (V::kContact) {
    // The peak force between output rows, tracked at every sub-step.
    if (d.stats.peak_contact > res.peak_joint2_force) {
      res.peak_joint2_force = d.stats.peak_contact;
      res.t_peak_joint2_force = d.stats.t_peak_contact;
    }
  }
  // A row's state is a step's end, which the steppers' peaks (taken at step starts) may miss.
  if (at_rows.peak_fn > d.stats.peak_fn) {
    d.stats.peak_fn = at_rows.peak_fn;
    d.stats.t_peak_fn = at_rows.t_peak_fn;
  }
  d.stats.max_penetration = std::max(d.stats.max_penetration, at_rows.max_penetration);
  for (int j = 0; j < 2; ++j) {
    d.stats.peak_fn_joint[j] = std::max(d.stats.peak_fn_joint[j], at_rows.peak_fn_joint[j]);
    d.stats.max_tilt_joint[j] = std::max(d.stats.max_tilt_joint[j], at_rows.max_tilt_joint[j]);
  }
  for (int e = 0; e < 4; ++e) d.stats.peak_fn_end[e] = std::max(d.stats.peak_fn_end[e], at_rows.peak_fn_end[e]);
  res.stats = d.stats;
  res.in_contact_at_end = s.anyInContact();
  res.final_q.assign(s.q.data(), s.q.data() + V::NQ);
  res.final_v.assign(s.v.data(), s.v.data() + V::NV);
  res.step_seconds = std::chrono::duration<double>(in_step).count();
  res.wall_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return res;
}

}  // namespace

RunResult simulate(const Scene& scene, const std::function<void(const Row&)>& sink, IntegratorKind kind,
                   const std::function<bool()>& stop) {
  return dispatchVariant(scene.model,
                         [&](auto tag) { return run<decltype(tag)>(scene.model, scene.run, sink, kind, stop); });
}

}  // namespace gimbalsim
