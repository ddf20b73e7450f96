#include "workprec.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
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
#include "gimbalsim/input/plain_decimal.hpp"
#include "gimbalsim/dynamics/stepper.hpp"
#include "gimbalsim/dynamics/simulate.hpp"
#include "gimbalsim/io/output_file.hpp"
#include "gimbalsim/pointing/target_profile.hpp"
#include "gimbalsim/program/stop_signal.hpp"

namespace gimbalsim::workprec {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double angleBetween(const Vec3& a, const Vec3& b) { return pointing::pointingError(a, b); }

}  // namespace

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
  // SIGINT/SIGTERM end a run inside its point (pass 68: a run of 1e9 steps went on after both)
  const RunResult res = simulate(sc, [&](const Row& r) { record(tr, r); }, kind, [] { return io::stopRequested(); });
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
  constexpr long long kChunk = 1 << 16;  // steps between two looks at a stop signal (the stepping is the same)
  const double t0 = threadCpuSeconds();
  for (long long k = 0; k < n; k += kChunk) {
    if (io::stopRequested() || !rk4.advance(s, k, std::min(n, k + kChunk), m.integrator.step).ok) return -1.0;
  }
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
      if (io::stopRequested()) return false;
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
    // a pass cut short by a signal is no reference: never cached
    if (io::stopRequested()) throw std::runtime_error(std::string("interrupted by ") + io::stopSignalName());
  } else {
    (void)sc, (void)dt, (void)r;
  }
}

/// One cache row "t,theta1,theta2,bore_x,bore_y,bore_z": six plain finite decimals as
/// the writer writes them, nothing else (a hex cell is no row this program wrote).
bool parseCacheRow(const std::string& line, double (&v)[6]) {
  std::size_t start = 0;
  for (int i = 0; i < 6; ++i) {
    const std::size_t comma = i < 5 ? line.find(',', start) : line.size();
    if (comma == std::string::npos) return false;
    if (readPlainDecimal(line.substr(start, comma - start), v[i]) != DecimalProblem::None) return false;
    start = comma + 1;
  }
  return true;
}

/// FNV-1a (64 bit) of the text after the header line: a cache whose rows were edited (one
/// deleted, another repeated: the count still holds) is not the reference it was written as.
/// Not a defence against an attacker, who could write a matching header: the cache is the
/// user's own file; this catches accidents.
std::string bodyChecksum(const std::string& text, std::size_t from) {
  std::uint64_t h = 14695981039346656037ull;
  for (std::size_t i = from; i < text.size(); ++i) h = (h ^ static_cast<unsigned char>(text[i])) * 1099511628211ull;
  std::ostringstream out;
  out << std::hex << h;
  return out.str();
}

/// Cache file format: one line "# key rows checksum self_consistency peak_contact peak_dt
/// stick..." then "t,theta1,theta2,bore_x,bore_y,bore_z" and exactly `rows` rows, each ended
/// by a newline. The count and the final newline tell a whole cache from one cut short (a
/// full disk, a copy stopped), even inside its last number; the checksum, one edited.
/// Returns "" when path holds the whole reference of key (read into r), kNoCache
/// when there is no file, else why the file cannot be used.
constexpr const char* kNoCache = "none";
std::string readCache(const std::string& path, const std::string& key, Reference& r) {
  std::error_code ec;
  const auto st = std::filesystem::symlink_status(path, ec);
  if (!std::filesystem::exists(st)) return kNoCache;
  if (!std::filesystem::is_regular_file(st)) return "not a regular file";
  std::ifstream file(path, std::ios::binary);
  std::stringstream whole;
  whole << file.rdbuf();
  const std::string text = whole.str();
  // A cut inside the last row can leave six numbers (a digit lost): only a whole file ends its row.
  if (!file || text.empty() || text.back() != '\n') return "cut short inside its last line";
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line)) return "empty or unreadable";
  std::istringstream hs(line);
  std::string hash, tag, checksum;
  long long rows = -1;
  StickSlip& ss = r.stick;
  hs >> tag >> hash >> rows >> checksum >> r.self_consistency >> r.rows.peak_contact >> r.peak_dt >> ss.dt >> ss.contact_time >>
      ss.below_va >> ss.band >> ss.slip >> ss.stick_entries >> ss.vt_sign_changes;
  if (tag != "#" || !hs || !(hs >> std::ws).eof() || rows <= 0) return "its first line is not a cache header";
  if (hash != key) return "made from other settings";
  std::getline(in, line);  // column names
  long long n = 0;
  while (std::getline(in, line)) {
    double v[6];
    if (!parseCacheRow(line, v)) return "row " + std::to_string(n + 1) + " is not six plain finite decimals";
    if (++n > rows) break;
    r.rows.t.push_back(v[0]);
    r.rows.theta1.push_back(v[1]);
    r.rows.theta2.push_back(v[2]);
    r.rows.bore.emplace_back(v[3], v[4], v[5]);
  }
  if (n != rows) return "holds " + std::to_string(n) + " rows where its header says " + std::to_string(rows);
  if (checksum != bodyChecksum(text, text.find('\n') + 1)) return "its rows are not the ones it was written with (edited)";
  return "";
}

void writeCache(const std::string& path, const std::string& key, const Reference& r) {
  std::ostringstream body;
  body << std::setprecision(17);
  const Trajectory& tr = r.rows;
  body << "t,theta1,theta2,bore_x,bore_y,bore_z\n";
  for (std::size_t i = 0; i < tr.t.size(); ++i) {
    body << tr.t[i] << ',' << tr.theta1[i] << ',' << tr.theta2[i] << ',' << tr.bore[i].x() << ','
         << tr.bore[i].y() << ',' << tr.bore[i].z() << '\n';
  }
  const std::string rows = body.str();
  std::ostringstream out;
  out << std::setprecision(17);
  const StickSlip& ss = r.stick;
  out << "# " << key << ' ' << tr.t.size() << ' ' << bodyChecksum(rows, 0) << ' ' << r.self_consistency << ' ' << tr.peak_contact << ' ' << r.peak_dt
      << ' ' << ss.dt << ' ' << ss.contact_time << ' ' << ss.below_va << ' ' << ss.band << ' ' << ss.slip << ' '
      << ss.stick_entries << ' ' << ss.vt_sign_changes << "\n"
      << rows;
  io::writeFileAtomically(path, out.str());  // throws io::OutputError naming the file
}

}  // namespace

Trajectory runRk4(const Scene& sc) { return rowsOf(sc, IntegratorKind::Rk4); }

double cpuSecondsOfRun(const Scene& sc) {
  return dispatchVariant(sc.model, [&](auto tag) { return cpuSecondsOfRunV<decltype(tag)>(sc); });
}

Reference reference(const Scene& sc, const std::string& key, const std::string& cache_dir, double peak_dt) {
  std::ostringstream hk;
  hk << std::hex << std::hash<std::string>{}(key + " peak_dt=" + formatNumber(peak_dt) + " dopri5-1e-12 v4");
  const std::string hash = hk.str();
  const std::string path = cache_dir + "/ref_" + sc.model.name + "_" + hash + ".csv";
  Reference r;
  if (const std::string why = readCache(path, hash, r); why.empty()) {
    r.from_cache = true;
    return r;
  } else if (why != kNoCache) {
    r = Reference{};
    r.cache_unused = path + ": " + why;
  }
  const double t0 = threadCpuSeconds();
  r.rows = rowsOf(sc, IntegratorKind::Reference);
  if (!r.rows.ok) throw std::runtime_error("reference run failed: " + r.rows.error);
  r.rows.peak_contact = 0.0;  // the row pass only sees rows; the fine pass sets it
  dispatchVariant(sc.model, [&](auto tag) { finePass<decltype(tag)>(sc, peak_dt, r); });
  r.cpu_seconds = threadCpuSeconds() - t0;
  try {  // the cache only saves time: a reference it cannot hold is still measured against
    std::filesystem::create_directories(cache_dir);
    writeCache(path, hash, r);
  } catch (const std::exception& e) {
    r.cache_unwritten = e.what();
  }
  return r;
}

}  // namespace gimbalsim::workprec
