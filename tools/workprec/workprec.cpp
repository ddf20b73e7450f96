#include "workprec.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "gimbalsim/dynamics/integrator.hpp"
#include "gimbalsim/input/key_registry.hpp"
#include "gimbalsim/dynamics/stepper.hpp"
#include "gimbalsim/dynamics/simulate.hpp"
#include "gimbalsim/io/output_file.hpp"
#include "gimbalsim/pointing/target_profile.hpp"

namespace gimbalsim::workprec {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double angleBetween(const Vec3& a, const Vec3& b) { return pointing::pointingError(a, b); }

}  // namespace

// ---------------------------------------------------------------- policies

std::vector<Policy> loadPolicies(const std::string& path) {
  YAML::Node root;
  std::string text, why;
  Problem refused;
  if (!readFile(path, text, &why)) throw std::runtime_error(path + ": cannot open policy file: " + why);
  if (!loadDocument(text, path, root, refused)) throw std::runtime_error(refused.text);
  const YAML::Node list = root["policies"];
  if (!list || !list.IsSequence()) throw std::runtime_error(path + ": expected a list 'policies:'");
  std::vector<Policy> out;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YAML::Node n = list[i];
    const std::string where = path + ":" + std::to_string(n.Mark().line + 1) + ": policy #" + std::to_string(i + 1);
    try {
      Policy p;
      for (const auto& kv : n) {
        const std::string k = kv.first.as<std::string>();
        if (k == "name") {
          p.name = kv.second.as<std::string>();
        } else if (k == "sets") {
          p.sets = kv.second.as<std::vector<std::string>>();
        } else if (k == "contact_only") {
          p.contact_only = kv.second.as<bool>();
        } else if (k == "sweep") {
          p.sweep_key = kv.second.as<std::string>();
        } else if (k == "values") {
          p.sweep_values = kv.second.as<std::vector<std::string>>();
        } else {
          throw std::runtime_error("unknown field '" + k + "'");
        }
      }
      if (p.name.empty()) throw std::runtime_error("needs a name");
      if (p.sweep_key.empty() != p.sweep_values.empty()) {
        throw std::runtime_error("'sweep' and 'values' go together");
      }
      for (const std::string& s : p.sets) {
        if (s.find('=') == std::string::npos) throw std::runtime_error("set '" + s + "' is not key=value");
      }
      out.push_back(std::move(p));
    } catch (const std::exception& e) {
      throw std::runtime_error(where + ": " + e.what());
    }
  }
  return out;
}

std::string expandSet(const std::string& set, double h) {
  const std::size_t at = set.find("{h}");
  if (at == std::string::npos) return set;
  double value = h;
  std::size_t end = at + 3;
  if (end < set.size() && set[end] == '*') {
    std::size_t used = 0;
    const std::string rest = set.substr(end + 1);
    value = h * std::stod(rest, &used);
    end += 1 + used;
  }
  return set.substr(0, at) + formatNumber(value) + set.substr(end);
}

// ---------------------------------------------------------------- runs

double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

namespace {

/// Appends one output row to a trajectory.
void record(Trajectory& tr, const Row& r) {
  tr.t.push_back(r.t);
  tr.theta1.push_back(r.theta1);
  tr.theta2.push_back(r.theta2);
  tr.bore.emplace_back(r.bore_x, r.bore_y, r.bore_z);
}

Trajectory rowsOf(const Scene& sc, IntegratorKind kind) {
  const Model& m = sc.model;
  Trajectory tr;
  const RunResult res = simulate(sc, [&](const Row& r) { record(tr, r); }, kind);
  tr.ok = res.ok;
  tr.error = res.error;
  tr.substeps = res.stats.substeps;
  tr.impacts = res.stats.impacts;
  // For the clearance joint joint2_force is the contact force, tracked at
  // every sub-step as well as at the rows.
  tr.peak_contact = m.hasClearance() ? res.peak_joint2_force : 0.0;
  tr.momentum_drift_rel =
      m.floating_base && res.momentum_scale > 0.0 ? res.max_drift_angular / res.momentum_scale : kNaN;
  return tr;
}

template <class V>
double cpuSecondsOfRunV(const Scene& sc) {
  const Model& m = sc.model;
  Data<V> d(m);
  State<V> s = initialState<V>(sc.run.initial);
  Input u;
  u.tau = sc.run.torque;
  const long long n = std::llround(sc.run.duration / m.integrator.step);
  Rk4Stepper<V> rk4(m, d, u);
  const double t0 = threadCpuSeconds();
  if (!rk4.advance(s, 0, n, m.integrator.step).ok) return -1.0;
  return threadCpuSeconds() - t0;
}

/// Samples the reference every dt for the peak contact force and the
/// stick/slip of the journal (clearance variants only).
template <class V>
void finePass(const Scene& sc, double dt, Reference& r) {
  if constexpr (V::kContact) {
    const Model& m = sc.model;
    Input u;
    u.tau = sc.run.torque;
    ReferenceStepper<V> integ(m, u);
    Data<V> d(m);
    State<V> s = initialState<V>(sc.run.initial);
    StickSlip& ss = r.stick;
    ss.dt = dt;
    const ContactParams& cp = m.bearing[1];
    const long long n = std::llround(sc.run.duration / dt);
    bool was_slipping = true;
    double prev_vt = 0.0;
    bool prev_contact = false;
    const long long per_row = std::llround(sc.run.output_interval / dt);
    // Every dt a row of the one output loop (stepper.hpp).
    const Advance done = forEachRow(integ, s, dt, n, 1, [&](const State<V>&, long long k) {
      if (const auto row = static_cast<std::size_t>(k / per_row); k % per_row == 0 && row < r.rows.bore.size()) {
        kinematics(m, d, s.q, s.v);
        r.self_consistency = std::max(r.self_consistency, angleBetween(boresight(m, d, s), r.rows.bore[row]));
      }
      bool touching = false;
      for (int e = 0; e < V::NC; ++e) touching = touching || endGap<V>(m, e, s.q, s.v).delta > 0.0;
      if (!touching) {
        prev_contact = false;
        return true;
      }
      forwardDynamics(m, d, s, u);
      int deepest = 0;  // the stick/slip statistics follow the end that carries the most
      for (int e = 0; e < V::NC; ++e) {
        r.rows.peak_contact = std::max(r.rows.peak_contact, std::hypot(d.contact[e].fn, d.contact[e].ft));
        if (d.contact[e].fn > d.contact[deepest].fn) deepest = e;
      }
      const ContactEval& c = d.contact[deepest];
      r.peak_dt = dt;
      if constexpr (V::kFriction) {
        const double a = std::fabs(c.vt);
        ss.contact_time += dt;
        const bool slipping = a >= cp.v_b;
        (a < cp.v_a ? ss.below_va : slipping ? ss.slip : ss.band) += dt;
        if (was_slipping && !slipping) ++ss.stick_entries;
        was_slipping = slipping;
        if (prev_contact && (c.vt > 0.0) != (prev_vt > 0.0)) ++ss.vt_sign_changes;
        prev_vt = c.vt;
      }
      prev_contact = true;
      return true;
    });
    if (!done.ok) throw std::runtime_error(std::string("reference (peak pass) stopped: ") + done.failure);
  } else {
    (void)sc, (void)dt, (void)r;
  }
}

/// Cache file format: one line "# key=... peak_contact=... peak_dt=... stick=..."
/// then "t,theta1,theta2,bore_x,bore_y,bore_z" rows.
bool readCache(const std::string& path, const std::string& key, Reference& r) {
  std::ifstream in(path);
  std::string line;
  if (!in || !std::getline(in, line)) return false;
  std::istringstream hs(line);
  std::string hash, tag;
  StickSlip& ss = r.stick;
  hs >> tag >> hash >> r.self_consistency >> r.rows.peak_contact >> r.peak_dt >> ss.dt >> ss.contact_time >> ss.below_va >>
      ss.band >> ss.slip >> ss.stick_entries >> ss.vt_sign_changes;
  if (tag != "#" || hash != key || !hs) return false;
  std::getline(in, line);  // column names
  while (std::getline(in, line)) {
    double v[6];
    char comma;
    std::istringstream ls(line);
    ls >> v[0] >> comma >> v[1] >> comma >> v[2] >> comma >> v[3] >> comma >> v[4] >> comma >> v[5];
    if (!ls) return false;
    r.rows.t.push_back(v[0]);
    r.rows.theta1.push_back(v[1]);
    r.rows.theta2.push_back(v[2]);
    r.rows.bore.emplace_back(v[3], v[4], v[5]);
  }
  return !r.rows.t.empty();
}

void writeCache(const std::string& path, const std::string& key, const Reference& r) {
  std::ostringstream out;
  out << std::setprecision(17);
  const StickSlip& ss = r.stick;
  out << "# " << key << ' ' << r.self_consistency << ' ' << r.rows.peak_contact << ' ' << r.peak_dt << ' ' << ss.dt << ' '
      << ss.contact_time << ' ' << ss.below_va << ' ' << ss.band << ' ' << ss.slip << ' '
      << ss.stick_entries << ' ' << ss.vt_sign_changes << "\n";
  out << "t,theta1,theta2,bore_x,bore_y,bore_z\n";
  const Trajectory& tr = r.rows;
  for (std::size_t i = 0; i < tr.t.size(); ++i) {
    out << tr.t[i] << ',' << tr.theta1[i] << ',' << tr.theta2[i] << ',' << tr.bore[i].x() << ','
        << tr.bore[i].y() << ',' << tr.bore[i].z() << '\n';
  }
  io::writeFileAtomically(path, out.str());  // throws io::OutputError naming the file
}

}  // namespace

Trajectory runRk4(const Scene& sc) { return rowsOf(sc, IntegratorKind::Rk4); }

double cpuSecondsOfRun(const Scene& sc) {
  return dispatchVariant(sc.model, [&](auto tag) { return cpuSecondsOfRunV<decltype(tag)>(sc); });
}

Reference reference(const Scene& sc, const std::string& key, const std::string& cache_dir, double peak_dt) {
  std::ostringstream hk;
  hk << std::hex << std::hash<std::string>{}(key + " peak_dt=" + formatNumber(peak_dt) + " dopri5-1e-12 v2");
  const std::string hash = hk.str();
  const std::string path = cache_dir + "/ref_" + sc.model.name + "_" + hash + ".csv";
  Reference r;
  if (readCache(path, hash, r)) {
    r.from_cache = true;
    return r;
  }
  r = Reference{};
  const double t0 = threadCpuSeconds();
  r.rows = rowsOf(sc, IntegratorKind::Reference);
  if (!r.rows.ok) throw std::runtime_error("reference run failed: " + r.rows.error);
  r.rows.peak_contact = 0.0;  // the row pass only sees rows; the fine pass sets it
  dispatchVariant(sc.model, [&](auto tag) { finePass<decltype(tag)>(sc, peak_dt, r); });
  r.cpu_seconds = threadCpuSeconds() - t0;
  std::filesystem::create_directories(cache_dir);
  writeCache(path, hash, r);
  return r;
}

// ---------------------------------------------------------------- errors

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

void writeCsv(const std::string& path, const std::vector<Point>& points) {
  std::ostringstream out;
  out << std::setprecision(10);
  for (std::size_t i = 0; i < kCsvColumns.size(); ++i) out << (i ? "," : "") << kCsvColumns[i];
  out << '\n';
  auto quoted = [](std::string s) {
    std::replace(s.begin(), s.end(), '"', '\'');
    return '"' + s + '"';
  };
  for (const Point& p : points) {
    out << quoted(p.scene) << ',' << quoted(p.policy) << ',' << p.h << ',' << p.substep << ','
        << p.event_tol << ',' << quoted(p.sweep_key) << ',' << quoted(p.sweep_value) << ','
        << (p.ok ? 1 : 0) << ',' << p.cpu_per_sim_s << ',' << p.repeats << ',' << p.bore_err_max << ','
        << p.bore_err_end << ',' << p.theta1_err_max << ',' << p.theta2_err_max << ','
        << p.peak_force_err_rel << ',' << p.momentum_drift_rel << ',' << p.substeps << ',' << p.impacts
        << ',' << (p.pareto ? 1 : 0) << ',' << quoted(p.note) << '\n';
  }
  io::writeFileAtomically(path, out.str());  // throws io::OutputError naming the file
}

}  // namespace gimbalsim::workprec
