#include "points.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "gimbalsim/io/csv_format.hpp"
#include "gimbalsim/io/output_file.hpp"
#include "gimbalsim/pointing/target_profile.hpp"

namespace gimbalsim::workprec {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double angleBetween(const Vec3& a, const Vec3& b) { return pointing::pointingError(a, b); }

}  // namespace

bool compare(const Trajectory& run, const Trajectory& ref, Point& p) {
  p.substeps = run.substeps;
  p.impacts = run.impacts;
  p.momentum_drift_rel = run.momentum_drift_rel;
  if (!run.ok) {
    p.note = run.error;
    return false;
  }
  if (run.t.size() != ref.t.size()) {
    p.note = "rows differ from the reference (" + std::to_string(run.t.size()) + " vs " +
             std::to_string(ref.t.size()) + "): output intervals differ";
    return false;
  }
  p.bore_err_max = p.theta1_err_max = p.theta2_err_max = 0.0;
  for (std::size_t i = 0; i < run.t.size(); ++i) {
    if (std::fabs(run.t[i] - ref.t[i]) > 1e-9) {
      p.note = "row times differ from the reference at row " + std::to_string(i);
      return false;
    }
    p.bore_err_max = std::max(p.bore_err_max, angleBetween(run.bore[i], ref.bore[i]));
    p.theta1_err_max = std::max(p.theta1_err_max, std::fabs(run.theta1[i] - ref.theta1[i]));
    p.theta2_err_max = std::max(p.theta2_err_max, std::fabs(run.theta2[i] - ref.theta2[i]));
  }
  p.bore_err_end = angleBetween(run.bore.back(), ref.bore.back());
  p.peak_force_err_rel = ref.peak_contact > 0.0
                             ? std::fabs(run.peak_contact - ref.peak_contact) / ref.peak_contact
                             : kNaN;
  if (!(ref.peak_contact > 0.0)) p.note = "peak_force_err_rel: no contact in the reference";  // nan's reason
  return true;
}

void markPareto(std::vector<Point>& points) {
  std::vector<Point*> ok;
  for (Point& p : points) {
    p.pareto = false;
    if (p.ok) ok.push_back(&p);
  }
  std::sort(ok.begin(), ok.end(), [](const Point* a, const Point* b) {
    return a->cpu_per_sim_s != b->cpu_per_sim_s ? a->cpu_per_sim_s < b->cpu_per_sim_s
                                                : a->bore_err_max < b->bore_err_max;
  });
  std::map<std::string, double> best;  // per scene: least error among cheaper points
  for (Point* p : ok) {
    auto it = best.find(p->scene);
    if (it == best.end() || p->bore_err_max < it->second) {
      p->pareto = true;
      best[p->scene] = p->bore_err_max;
    }
  }
}

const Point* cheapestFor(const std::vector<Point>& points, const std::string& scene, double target) {
  const Point* best = nullptr;
  for (const Point& p : points) {
    if (!p.ok || p.scene != scene || !(p.bore_err_max <= target)) continue;
    if (!best || p.cpu_per_sim_s < best->cpu_per_sim_s) best = &p;
  }
  return best;
}

const std::vector<std::string> kCsvColumns = {
    "scene",         "policy",          "h_s",           "substep_s",        "event_tol_s",
    "sweep_key",     "sweep_value",     "ok",            "cpu_s_per_sim_s",  "repeats",
    "bore_err_max_rad", "bore_err_end_rad", "theta1_err_max_rad", "theta2_err_max_rad",
    "peak_force_err_rel", "momentum_drift_rel", "substeps", "impacts", "pareto", "note"};

std::string csvText(const std::vector<Point>& points) {
  std::ostringstream out;
  auto n = [](double x) {  // the CSV convention's numbers (io/csv_format.hpp)
    std::string s;
    io::appendCsvNumber(s, x);
    return s;
  };
  for (std::size_t i = 0; i < kCsvColumns.size(); ++i) out << (i ? "," : "") << kCsvColumns[i];
  out << '\n';
  const auto text = [](const std::string& s) { return io::csvTextCell(s); };  // unquoted (CSV convention)
  for (const Point& p : points) {
    out << text(p.scene) << ',' << text(p.policy) << ',' << n(p.h) << ',' << n(p.substep) << ','
        << n(p.event_tol) << ',' << text(p.sweep_key) << ',' << text(p.sweep_value) << ','
        << (p.ok ? 1 : 0) << ',' << n(p.cpu_per_sim_s) << ',' << p.repeats << ',' << n(p.bore_err_max) << ','
        << n(p.bore_err_end) << ',' << n(p.theta1_err_max) << ',' << n(p.theta2_err_max) << ','
        << n(p.peak_force_err_rel) << ',' << n(p.momentum_drift_rel) << ',' << p.substeps << ',' << p.impacts
        << ',' << (p.pareto ? 1 : 0) << ',' << text(p.note) << '\n';
  }
  return out.str();
}

}  // namespace gimbalsim::workprec
