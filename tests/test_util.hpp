// Shared helpers of the test suite.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "gimbalsim/dynamics/integrator.hpp"
#include "gimbalsim/dynamics/observables.hpp"
#include "gimbalsim/scene/scene.hpp"
#ifdef GIMBALSIM_TEST_PLANT
#include "gimbalsim/firmware_sim/plant_scene.hpp"
#endif
#include "gimbalsim/pointing/target_profile.hpp"

namespace gimbalsim::test {

inline std::string scenePath(const std::string& name) {
  return std::string(GIMBALSIM_SCENES_DIR) + "/" + name + ".yaml";
}

#ifdef GIMBALSIM_CONTROLLER_CONFIG_DIR
/// The controller's default configuration file (controllers/config/default.yaml).
inline std::string defaultControllerConfig() {
  return std::string(GIMBALSIM_CONTROLLER_CONFIG_DIR) + "/default.yaml";
}
#endif

inline Scene scene(const std::string& name, const std::vector<std::string>& sets = {}) {
  return loadScene(scenePath(name), sets);
}

#ifdef GIMBALSIM_TEST_PLANT
/// A scene file as the plant loads it (with its sensors.* keys).
inline firmware::PlantScene plant(const std::string& name, const std::vector<std::string>& sets = {}) {
  return firmware::loadPlantScene(scenePath(name), sets);
}
#endif

/// The physics of a scene file (most tests need nothing else).
inline Model model(const std::string& name, const std::vector<std::string>& sets = {}) {
  return scene(name, sets).model;
}

/// Steps s for n steps of the model's h under input u; fails the test on a bad status.
template <class V>
void advance(const Model& m, Data<V>& d, State<V>& s, long long n, const Input& u) {
  for (long long k = 0; k < n; ++k) {
    const StepResult st = step(m, d, s, u);
    ASSERT_EQ(st.status, StepStatus::Ok) << describe(st.status) << " at t = " << st.time;
  }
}

/// Runs a fresh state of variant V of a scene (its constant torques) to time T.
template <class V>
State<V> runTo(const Scene& sc, double T) {
  const Model& m = sc.model;
  Data<V> d(m);
  State<V> s = initialState<V>(sc.run.initial);
  advance(m, d, s, std::llround(T / m.integrator.step), Input{sc.run.torque});
  return s;
}

/// Momentum and kinetic energy of a state.
template <class V>
Momentum momentumOf(const Model& m, const State<V>& s) {
  Data<V> d(m);
  kinematics(m, d, s.q, s.v);
  return momentum(m, d, s);
}

/// Boresight of a state (inertial frame).
template <class V>
Vec3 boresightOf(const Model& m, const State<V>& s) {
  Data<V> d(m);
  kinematics(m, d, s.q, s.v);
  return boresight(m, d, s);
}

/// Angle between two directions [rad] (the tree's one such function).
inline double angleBetween(const Vec3& a, const Vec3& b) { return pointing::pointingError(a, b); }

}  // namespace gimbalsim::test
