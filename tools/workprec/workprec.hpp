// Work-precision measurement: CPU time per simulated second against error to
// a reference solution, for each step size and contact sub-stepping policy.
// A tool, not on the real-time path: it allocates and throws freely.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "gimbalsim/dynamics/run_spec.hpp"
#include "gimbalsim/dynamics/spatial.hpp"

namespace gimbalsim::workprec {

/// A trajectory sampled at output rows: what the errors are computed from.
struct Trajectory {
  std::vector<double> t;                ///< [s]
  std::vector<double> theta1, theta2;   ///< [rad]
  std::vector<Vec3> bore;               ///< boresight unit vector, inertial
  double peak_contact = 0.0;            ///< max |F_n n + F_t t| over the run [N]
  double momentum_drift_rel = 0.0;      ///< max |L(t) - L(0)| / momentum scale [-]
  long long substeps = 0, impacts = 0;
  bool ok = true;
  std::string error;                    ///< why the run stopped
};

/// Stick and slip of the clearance joint, from a finely sampled run.
struct StickSlip {
  double dt = 0.0;                  ///< sample spacing [s]
  double contact_time = 0.0;        ///< time in contact [s]
  double below_va = 0.0;            ///< in contact with |v_t| < v_a [s] (no friction)
  double band = 0.0;                ///< v_a <= |v_t| < v_b (friction below mu F_n: sticking) [s]
  double slip = 0.0;                ///< |v_t| >= v_b (full Coulomb friction: slipping) [s]
  long long stick_entries = 0;      ///< transitions from slip to |v_t| < v_b
  long long vt_sign_changes = 0;    ///< reversals of v_t while in contact
};

/// The reference of one scene: rows at the output interval (Dormand-Prince
/// at 1e-12, IntegratorKind::Reference) plus a finely sampled pass for the
/// peak contact force and the stick-slip figures.
struct Reference {
  Trajectory rows;
  double peak_dt = 0.0;          ///< sampling of the peak pass [s]
  StickSlip stick;
  /// Max boresight angle between the row pass and the peak pass at the row
  /// times: two integrations of the same problem with different stopping
  /// points, so a bound on the reference's own error [rad].
  double self_consistency = 0.0;
  double cpu_seconds = 0.0;      ///< to compute it (0 when read from the cache)
  bool from_cache = false;
  /// Why a file under the cache's name was not read ("" when none was there or it
  /// was read): cut short, unreadable, not a file. The reference was computed.
  std::string cache_unused;
  /// Why the computed reference could not be cached ("" when it was).
  std::string cache_unwritten;
};

/// Computes the reference of m, or reads it from cache_dir when a file there
/// was made from the same scene text, overrides and settings (key) and holds
/// every row its header counts. Only a failed reference run throws; a cache
/// that cannot be read or written is said in cache_unused / cache_unwritten.
Reference reference(const Scene& sc, const std::string& key, const std::string& cache_dir,
                    double peak_dt);

/// The RK4 run (sim.step and the policy's settings) sampled at output rows.
Trajectory runRk4(const Scene& sc);

/// Thread CPU seconds of one RK4 run of m (stepping only, no output), or a
/// negative number when the run stops.
double cpuSecondsOfRun(const Scene& sc);

/// CPU time of the calling thread [s] (CLOCK_THREAD_CPUTIME_ID).
double threadCpuSeconds();

/// Median of v (v not empty).
double median(std::vector<double> v);

}  // namespace gimbalsim::workprec
