#include "gimbalsim/run_output/run_output.hpp"

#include <cstdio>

#include "gimbalsim/io/csv_format.hpp"

namespace gimbalsim::io {

std::string csvHeader(const ColumnSet& cols) {
  std::string h;
  for (int k = 0; k < cols.count; ++k) {
    const int i = cols.index[k];
    h.append(k ? "," : "").append(csvName(kColumns[i], kColumnUnits[i]));
  }
  return h + "\n";
}

void appendCsvRow(std::string& out, std::span<const double, kNumColumns> row, const ColumnSet& cols) {
  for (int k = 0; k < cols.count; ++k) {
    if (k) out += ',';
    appendCsvNumber(out, row[cols.index[k]]);
  }
  out += '\n';
}

namespace {
/// x, or null when `present` is false.
nlohmann::json valueOrNull(bool present, double x) {
  return present ? nlohmann::json(x) : nlohmann::json(nullptr);
}
/// The momentum drift over the run. A drift needs a step, a relative one a scale: over a run stopped in its first
/// step, or one in which nothing turned, they are null with the reason (0 read as "held", pass 82).
nlohmann::json momentumDrift(const RunResult& r) {
  nlohmann::json d = {{"linear_max_abs_Ns", r.max_drift_linear},
                      {"angular_max_abs_Nms", r.max_drift_angular},
                      {"angular_scale_Nms", r.momentum_scale},
                      {"angular_relative", nullptr}};
  if (!(r.t_end > 0.0)) {
    for (const char* k : {"linear_max_abs_Ns", "angular_max_abs_Nms", "angular_scale_Nms"}) d[k] = nullptr;
    d["reason"] = "the run stopped in its first step: no drift over no step";
  } else if (!(r.momentum_scale > 0.0)) {
    d["reason"] = "angular_relative: the angular momentum scale is 0 (nothing turned): no relative drift";
  } else {
    d["angular_relative"] = r.max_drift_angular / r.momentum_scale;
  }
  return d;
}

}  // namespace

nlohmann::json runSummary(const Model& m, const RunResult& r, const std::string& scene,
                          const std::string& integrator_kind) {
  using nlohmann::json;
  const RunStats& st = r.stats;
  auto named = [](const std::vector<std::string>& names, const std::vector<double>& values) {
    json o;
    for (size_t i = 0; i < values.size(); ++i) o[names[i]] = values[i];
    return o;
  };
  json j = {
      {"scene", scene},
      {"name", m.name},
      {"variant", variantName(m)},
      {"status", r.ok ? "ok" : r.stop.kind == RunStop::Kind::Interrupted ? "interrupted" : "failed"},
      {"t_end_s", r.t_end},
      {"rows", r.rows},
      {"impacts", st.impacts},
      {"separations", st.separations},
      {"peak_contact_force_N", st.peak_fn},
      {"t_peak_contact_force_s", valueOrNull(st.peak_fn > 0, st.t_peak_fn)},
      {"peak_joint2_force_N", r.peak_joint2_force},
      {"t_peak_joint2_force_s", r.t_peak_joint2_force},
      {"max_penetration_m", st.max_penetration},
      // Continuous contact: the contact that began at the last onset lasted to the end.
      {"continuous_contact_from_s",
       valueOrNull(m.hasClearance() && r.in_contact_at_end && st.last_onset_time >= 0, st.last_onset_time)},
      {"final_state",
       {{"t", r.t_end}, {"q", named(coordinateNamesQ(m), r.final_q)}, {"v", named(coordinateNamesV(m), r.final_v)}}},
      {"momentum_drift", momentumDrift(r)},
      {"wall_time_s", r.wall_seconds},
      {"step_time_s", r.step_seconds},
      {"integrator", {{"kind", integrator_kind}, {"step_s", m.integrator.step}}}};
  // Per clearance joint: its kind, impacts at its ends, largest normal force
  // at any of its ends and, for a spatial joint, the largest tilt angle.
  for (int jt = 0; jt < 2; ++jt) {
    const ClearanceKind kind = jt == 0 ? m.joint1_kind : m.joint2_kind;
    if (kind == ClearanceKind::Ideal) continue;
    json o = {{"kind", kindName(kind)},
              {"impacts", st.impacts_joint[jt]},
              {"peak_contact_force_N", st.peak_fn_joint[jt]}};
    if (kind == ClearanceKind::Spatial) {
      // Its two bearing ends, -L/2 and +L/2 along the bearing axis k.
      const int e0 = jt == 0 ? 0 : contactEnds(m.joint1_kind);
      o["max_tilt_rad"] = st.max_tilt_joint[jt];
      for (int side = 0; side < 2; ++side) {
        o["ends"][side == 0 ? "minus" : "plus"] = {{"impacts", st.impacts_end[e0 + side]},
                                                   {"peak_contact_force_N", st.peak_fn_end[e0 + side]}};
      }
    }
    j["clearance_joints"][jt == 0 ? "joint1" : "joint2"] = o;
  }
  if (r.integrator == IntegratorKind::Rk4) {
    // The RK4's own counters and settings; the reference has none of them.
    j["steps"] = st.steps;
    j["substeps"] = st.substeps;
    j["event_iterations"] = st.event_iterations;
    j["max_substeps_in_a_step"] = st.max_substeps_in_step;
    j["straddle_retries"] = st.straddle_retries;
    j["adaptive_rejected_substeps"] = st.rejected_substeps;
    j["adaptive_forced_substeps"] = st.forced_substeps;
    j["min_impact_duration_s"] = valueOrNull(st.min_impact_duration > 0, st.min_impact_duration);
    j["integrator"]["substep_s"] = m.integrator.substep;
    j["integrator"]["event_tol_s"] = m.integrator.event_tol;
  }
  if (!r.ok) {
    j["error"] = r.error;
    // What stopped the run, as codes: the scene key of the limit ("" when no
    // setting names it), the step status and the time.
    j["stop"] = {{"key", r.stop.key}, {"step_status", describe(r.stop.step.status)}, {"time_s", r.stop.time}};
  }
  return j;
}

}  // namespace gimbalsim::io
