// A scene's plant stepped call by call, whichever variant its Model is: the
// stepping object behind the Python package's Simulator. One virtual call per
// step() or run(), then the templated step of the variant; nothing in step(),
// run() or output() allocates or throws.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "gimbalsim/dynamics/observables.hpp"
#include "gimbalsim/dynamics/run_spec.hpp"
#include "gimbalsim/dynamics/step_result.hpp"

namespace gimbalsim {

/// A State<V> without its type: what a checkpoint holds (state.hpp), plus the
/// variant it belongs to. Restoring it and stepping on gives the same bits as
/// never having stopped.
struct SavedState {
  std::string variant;           ///< variantName() of the model it was taken from
  double t = 0.0;                ///< [s]
  std::vector<double> q, v;      ///< generalised coordinates and velocities (state.hpp)
  /// each contact end's side and impact velocity [m/s] (state.hpp: joint 1's
  /// ends first; none for ideal joints, one per planar joint, two per spatial)
  std::vector<bool> in_contact;
  std::vector<double> v0;
  int friction_mode = 0;
  double vt_floor = 0.0;         ///< [m/s]
  double h_next = 0.0;           ///< [s]
};

class Simulator {
 public:
  /// The scene's model at its initial state (run.initial); the torques are
  /// the scene's (torque.tau1, torque.tau2) until the first step, so that
  /// output() at t = 0 is simulate()'s first row.
  explicit Simulator(const Scene& scene);
  ~Simulator();
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;

  const Model& model() const;
  /// Simulated time [s]: k sim.step after k steps from t = 0.
  double time() const noexcept;

  /// n steps of sim.step with joint torques tau = (tau1, tau2) [N m] held
  /// (sub-stepping inside, as everywhere). On a status other than Ok the
  /// state is the last good one (inside the failing step).
  StepResult step(const Vec2& tau, long long n = 1) noexcept;

  /// n steps, step i with torques tau[2 i], tau[2 i + 1] [N m]; after each,
  /// the output row into rows[i * kNumColumns ...]. `done` counts the steps
  /// that succeeded (their rows are written).
  StepResult run(const double* tau, long long n, double* rows, long long& done) noexcept;

  /// The output row (observables.hpp) of the current state under the last torques.
  Row output() noexcept;

  SavedState save() const;
  /// Throws std::invalid_argument naming each bad field (checkSavedState, saved_state.hpp).
  void restore(const SavedState& saved);

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace gimbalsim
