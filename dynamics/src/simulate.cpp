#include "gimbalsim/dynamics/simulate.hpp"

#include <chrono>
#include <cmath>
#include <sstream>

#include "gimbalsim/dynamics/integrator.hpp"
#include "gimbalsim/dynamics/invariants.hpp"
#include "gimbalsim/dynamics/reference_integrator.hpp"

namespace gimbalsim {

std::string variantName(const Model& m) {
  std::string s = m.floating_base ? "floating" : "fixed";
  s += m.clearance ? "_clearance" : "_ideal";
  if (frictionActive(m)) s += "_friction";
  return s;
}

std::vector<std::string> coordinateNamesQ(const Model& m) {
  std::vector<std::string> n;
  if (m.floating_base) n = {"base_x", "base_y", "base_z", "base_qw", "base_qx", "base_qy", "base_qz"};
  n.push_back("theta1");
  if (m.clearance) {
    n.push_back("ecc_x");
    n.push_back("ecc_y");
  }
  n.push_back("theta2");
  return n;
}

std::vector<std::string> coordinateNamesV(const Model& m) {
  std::vector<std::string> n;
  if (m.floating_base) n = {"base_wx", "base_wy", "base_wz", "base_vx(base frame)", "base_vy(base frame)", "base_vz(base frame)"};
  n.push_back("dtheta1");
  if (m.clearance) {
    n.push_back("decc_x");
    n.push_back("decc_y");
  }
  n.push_back("dtheta2");
  return n;
}

namespace {

bool rowFinite(const Row& r) {
  const double* p = rowData(r);
  for (int i = 0; i < kNumColumns; ++i) {
    if (!std::isfinite(p[i])) return false;
  }
  return true;
}

template <class V>
RunResult run(const Model& m, const std::function<void(const Row&)>& sink, IntegratorKind kind) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  RunResult res;
  Data<V> d(m);
  State<V> s = initialState<V>(m);
  Input u;
  u.tau = m.torque;
  const long long n_steps = std::llround(m.duration / m.integrator.step);
  const long long out_every = std::max<long long>(1, std::llround(m.output_interval / m.integrator.step));
  Clock::duration in_step{0};
  InvariantMonitor inv(m);

  auto emit = [&](const State<V>& st) -> bool {
    const Row r = observe(m, d, st, u);
    if (!rowFinite(r)) {
      std::ostringstream os;
      os << "non-finite output at t = " << st.t << " s";
      res.ok = false;
      res.error = os.str();
      return false;
    }
    const Momentum mo = momentum(m, d, st);
    inv.feed(r, mo.scale, mo.scale_linear);
    res.max_drift_linear = inv.maxDriftLinear();
    res.max_drift_angular = inv.maxDriftAngular();
    res.momentum_scale = inv.angularScale();
    res.linear_scale = inv.linearScale();
    res.energy_rise_rel = inv.energyRiseRel();
    if (const std::string why = inv.violation(); !why.empty()) {
      std::ostringstream os;
      os << "simulation stopped at t = " << st.t << " s: " << why;
      res.ok = false;
      res.error = os.str();
      return false;
    }
    if (r.joint2_force > res.peak_joint2_force) {
      res.peak_joint2_force = r.joint2_force;
      res.t_peak_joint2_force = r.t;
    }
    ++res.rows;
    res.t_end = st.t;
    sink(r);
    return true;
  };

  if (kind == IntegratorKind::Reference) {
    ReferenceIntegrator<V> ref(m, u);
    if (emit(s)) {
      const long long n_out = (n_steps + out_every - 1) / out_every;
      for (long long k = 1; k <= n_out; ++k) {
        const double t_next = std::min(k * out_every, n_steps) * m.integrator.step;
        const auto a = Clock::now();
        const bool ok = ref.advanceTo(s, t_next);
        in_step += Clock::now() - a;
        if (!ok) {
          std::ostringstream os;
          os << "reference integration stopped before t = " << t_next << " s: " << ref.failure();
          res.ok = false;
          res.error = os.str();
          break;
        }
        if (!emit(s)) break;
      }
    }
    d.stats.impacts = ref.impacts();
  } else if (emit(s)) {
    for (long long k = 1; k <= n_steps; ++k) {
      const auto a = Clock::now();
      const StepStatus st = step(m, d, s, u);
      in_step += Clock::now() - a;
      if (st != StepStatus::Ok) {
        std::ostringstream os;
        os << "simulation stopped at t = " << d.fail_time << " s: " << describe(st);
        if (st == StepStatus::NonFinite || st == StepStatus::VelocityLimit) {
          const auto qn = coordinateNamesQ(m);
          const auto vn = coordinateNamesV(m);
          const int i = d.fail_index;
          if (i >= 0 && i < static_cast<int>(vn.size())) os << " (in " << vn[i] << ")";
          if (i < 0 && -1 - i < static_cast<int>(qn.size())) os << " (in " << qn[-1 - i] << ")";
        }
        if (st == StepStatus::PenetrationLimit) {
          os << " (penetration " << d.stats.max_penetration << " m, clearance " << m.contact.clearance << " m)";
        }
        if (st == StepStatus::SubstepTooLong) {
          os << " (impact lasting about " << d.fail_detail << " s, " << d.fail_detail / m.integrator.substep
             << " sub-steps of " << m.integrator.substep << " s; sim.min_substeps_per_impact "
             << m.integrator.min_substeps_per_impact << ")";
        }
        res.ok = false;
        res.error = os.str();
        break;
      }
      // Snap time to the step grid so output times do not drift.
      s.t = static_cast<double>(k) * m.integrator.step;
      if (k % out_every == 0 || k == n_steps) {
        if (!emit(s)) break;
      }
    }
  }
  if constexpr (V::kClearance) {
    // The peak force between output rows, tracked at every sub-step.
    if (d.stats.peak_contact > res.peak_joint2_force) {
      res.peak_joint2_force = d.stats.peak_contact;
      res.t_peak_joint2_force = d.stats.t_peak_contact;
    }
  }
  res.stats = d.stats;
  res.in_contact_at_end = s.in_contact;
  res.final_q.assign(s.q.data(), s.q.data() + V::NQ);
  res.final_v.assign(s.v.data(), s.v.data() + V::NV);
  res.step_seconds = std::chrono::duration<double>(in_step).count();
  res.wall_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return res;
}

}  // namespace

RunResult simulate(const Model& m, const std::function<void(const Row&)>& sink, IntegratorKind kind) {
  return dispatchVariant(m, [&](auto tag) { return run<decltype(tag)>(m, sink, kind); });
}

}  // namespace gimbalsim
